// Fuzz target: the JSON scene parser, then what every command does with a parsed scene before it
// touches a device (prepareScene: flattening, light CDF, BVH build). Relative mesh paths resolve in
// tests/data, so inputs naming its glTF files reach the glTF loader through the `mesh` shape.
// Every input must end in a Scene or one vktg::Error; anything else is a finding.
// vktg-fuzz-seeds: scenes/*.json tests/data/optimize/terrain_free.json
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vktg::fuzz::expectOnlyVktgErrors([&] {
    vktg::Scene scene = vktg::parseSceneJson(text, "fuzz.json", VKTG_TEST_DATA);
    vktg::fuzz::prepareIfSmall(scene);
  });
  return 0;
}
