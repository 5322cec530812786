// Fuzz target: scan files (`vktg render --scan`, src/scene/scan.h). Every input is parsed against
// a point-sensor scene (the confocal-scan experiment's, whose laser a grid may move) and a
// perspective one (the default room), and every view's camera is derived as the render derives it.
// Every input must end in a scan or one vktg::Error.
// vktg-fuzz-seeds: experiments/*/scan.json tests/data/scan/*.json
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scene/scan.h"

namespace {

const vktg::Scene& sensorScene() {
  static const vktg::Scene scene =
      vktg::loadScene(std::filesystem::path(VKTG_TEST_DATA) / ".." / ".." / "experiments" / "confocal_scan" / "scene.json");
  return scene;
}

const vktg::Scene& pinholeScene() {
  static const vktg::Scene scene = vktg::defaultScene();
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const vktg::Scene* scene : {&sensorScene(), &pinholeScene()})
    vktg::fuzz::expectOnlyVktgErrors([&] {
      const vktg::Scan scan = vktg::parseScanJson(text, "fuzz.scan.json", *scene);
      for (const vktg::SceneView& view : scan.views) (void)vktg::cameraSeenFrom(scene->camera, view);
    });
  return 0;
}
