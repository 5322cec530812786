// Fuzz target: what `vktg optimize` reads before it renders. An input that starts with the EXR
// magic number is a target image: it becomes target 0 ("front") of tests/data/optimize/complete.json
// and goes through loadTargetImage (decoding, size and layer checks against the view and gate,
// finiteness). Any other input is an experiment file, parsed with its scene and relative paths
// resolved in tests/data/optimize, then every target's scene is derived (view, lights, gate) and
// prepared like a render's. Every input must end in an experiment or one vktg::Error.
// vktg-fuzz-seeds: tests/data/optimize/*.json tests/data/optimize/*.exr experiments/*/*.experiment.json
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "fuzz_support.h"
#include "opt/experiment.h"

namespace {

const std::filesystem::path kBase = std::filesystem::path(VKTG_TEST_DATA) / "optimize";

bool isExr(const uint8_t* data, size_t size) {
  static const uint8_t kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  return size >= 4 && std::memcmp(data, kMagic, 4) == 0;
}

void fuzzTargetImage(const uint8_t* data, size_t size) {
  static const vktg::fuzz::TemporaryDirectory dir;
  static const vktg::Experiment base = vktg::loadExperiment(kBase / "complete.json");
  const std::filesystem::path path = dir.path() / "target.exr";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  vktg::Experiment experiment = base;
  experiment.targets.at(0).image = path;
  vktg::fuzz::expectOnlyVktgErrors([&] { vktg::loadTargetImage(experiment, 0); });
}

void fuzzExperimentFile(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vktg::fuzz::expectOnlyVktgErrors([&] {
    const vktg::Experiment experiment = vktg::parseExperimentJson(text, "fuzz.experiment.json", kBase);
    for (const vktg::Target& target : experiment.targets)
      vktg::fuzz::prepareIfSmall(vktg::sceneForTarget(experiment.scene, target));
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (isExr(data, size)) fuzzTargetImage(data, size);
  else fuzzExperimentFile(data, size);
  return 0;
}
