// Fuzz target: the glTF loader (loadGltfScene, .gltf text or .glb binary by the input's magic),
// then prepareScene like every command. tinygltf reads files, so each input is written to a
// private temporary directory first. Every input must end in a Scene or one vktg::Error.
// vktg-fuzz-seeds: tests/data/*.gltf tests/data/*.glb
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "fuzz_support.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const vktg::fuzz::TemporaryDirectory dir;
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::filesystem::path path = dir.path() / (binary ? "input.glb" : "input.gltf");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  vktg::fuzz::expectOnlyVktgErrors([&] {
    vktg::Scene scene = vktg::loadGltfScene(path);
    vktg::fuzz::prepareIfSmall(scene);
  });
  return 0;
}
