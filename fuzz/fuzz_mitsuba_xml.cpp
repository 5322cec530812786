// Fuzz target: the Mitsuba XML scene reader (loadMitsubaXml: includes, defaults, substitution,
// plugins, the nlos_capture_meter's scan), then prepareScene like every command. The input is
// written as input.xml into a private copy of tests/data/mitsuba beside tests/data/meshes, so that
// its includes and mesh files resolve as the seeds' do; an include of input.xml itself is a cycle.
// Every input must end in a scene or one vktg::Error.
// vktg-fuzz-links: vktg_scene
// vktg-fuzz-seeds: tests/data/mitsuba/*.xml tests/data/mitsuba/parts/*.xml scenes/*.xml
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "fuzz_support.h"
#include "scene/mitsuba_xml.h"
#include "vktg/scene.h"

namespace {

namespace fs = std::filesystem;

// tests/data/mitsuba and tests/data/meshes, copied once, side by side.
fs::path preparedFolder() {
  static const vktg::fuzz::TemporaryDirectory dir;
  static const fs::path folder = [] {
    const fs::path data = VKTG_TEST_DATA;
    fs::copy(data / "mitsuba", dir.path() / "mitsuba", fs::copy_options::recursive);
    fs::copy(data / "meshes", dir.path() / "meshes", fs::copy_options::recursive);
    return dir.path() / "mitsuba";
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path path = preparedFolder() / "input.xml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  vktg::fuzz::expectOnlyVktgErrors([&] {
    const vktg::MitsubaScene m = vktg::loadMitsubaXml(path, {});
    vktg::fuzz::prepareIfSmall(m.scene);
  });
  return 0;
}
