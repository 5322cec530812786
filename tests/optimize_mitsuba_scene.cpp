// Optimisation of a mitransient NLOS scene as the file is (docs/optimize.md, "scene"): the XML and
// its OBJ hidden object unchanged, the parameters given in the experiment's scene object. The
// capture meter's own scan is a target, and reads the same loss and gradient, bit for bit, as the
// HDF5 capture vktg renders from the same file; and the hidden object, moved off its place, is
// pulled back to it by a few iterations of `vktg optimize`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "optimize/optimize.h"
#include "support/cli_runner.h"
#include "support/experiment_run.h"
#include "support/gpu_context.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::TempDir;

const fs::path kNlos = fs::path(VKTG_TEST_DATA) / "mitsuba" / "nlos_confocal.xml";

// The XML scene at a 4 x 4 grid, its hidden object free to move towards the wall (+y).
json sceneObject() {
  return {{"file", kNlos.string()},
          {"defines", {{"grid", 4}, {"spp", 64}}},
          {"parameters", {{{"name", "hidden_y"}, {"type", "translate"}, {"shape", "hidden"}, {"axis", {0, 1, 0}}}}}};
}

TEST(OptimizeMitsubaScene, TheMetersScanIsTheTargetItsRenderedCaptureIs) {
  TempDir dir;
  for (const char* out : {"cube.exr", "cube.hdf5"})
    test::runVktgOk({"render", kNlos.string(), "-D", "grid=4", "-D", "spp=32", "--seed", "5", "--quiet", "--out", out}, dir);
  const json base = {{"version", 1},
                     {"scene", sceneObject()},
                     {"parameters", {{{"name", "hidden_y"}, {"initial", 0.04}}}},
                     {"render", {{"spp", 16}}},
                     {"stop", {{"iterations", 1}}}};
  json own = base, capture = base;
  own["targets"] = {{{"name", "wall"}, {"image", "cube.exr"}}};
  capture["targets"] = {{{"name", "wall"}, {"capture", "cube.hdf5"}, {"lights", {"laser"}}}};
  test::writeJsonFile(dir / "own.json", own);
  test::writeJsonFile(dir / "capture.json", capture);

  Optimization fromScan(test::testContext(), test::optimizeOptions(dir / "own.json", dir / "own_run"));
  const Evaluation a = fromScan.evaluate();
  Optimization fromCapture(test::testContext(), test::optimizeOptions(dir / "capture.json", dir / "capture_run"));
  const Evaluation b = fromCapture.evaluate();
  ASSERT_EQ(a.targetLosses.size(), 16u) << "one target per wall point of the 4 x 4 grid";
  EXPECT_EQ(b.targetLosses, a.targetLosses);
  EXPECT_GT(a.loss, 0);
  ASSERT_EQ(a.gradient.theta.size(), 1u);
  EXPECT_TRUE(test::sameBits(b.gradient.theta, a.gradient.theta)) << a.gradient.theta[0] << " vs " << b.gradient.theta[0];
  // Raised 4 cm towards the wall, every path is shorter than the target's: the loss falls as the
  // object moves back down.
  EXPECT_GT(a.gradient.theta[0], 0) << "a zero or wrongly signed gradient";
}

TEST(OptimizeMitsubaScene, TheHiddenObjectReturnsToItsPlace) {
  TempDir dir;
  const json experiment = {{"version", 1},
                           {"scene", sceneObject()},
                           {"parameters", {{{"name", "hidden_y"}, {"initial", 0.06}, {"truth", 0}, {"range", {-0.2, 0.2}}}}},
                           {"targets", {{{"name", "wall"}, {"image", {{"synthesize", {{"spp", 512}}}}}}}},
                           // The capture's values are tiny (a 0.2 rad projector's spot lights the hidden
                           // object at 1e-8): a relative loss, which its scale does not enter.
                           {"loss", {{"type", "relative_l2"}, {"epsilon", 0.05}}},
                           {"optimizer", {{"type", "adam"}, {"learning_rate", 0.01}, {"beta1", 0.5}}},
                           {"render", {{"spp", 32}}},
                           {"stop", {{"iterations", 12}}}};
  test::writeJsonFile(dir / "experiment.json", experiment);
  test::runVktgOk({"optimize", "experiment.json", "--out", "run", "--quiet"}, dir);
  std::ifstream stream(dir / "run" / "parameters.json");
  const json parameters = json::parse(stream);
  ASSERT_EQ(parameters.size(), 1u);
  const double final = parameters[0]["final"].get<double>();
  std::printf("hidden_y: 0.06 -> %.4f (truth 0)\n", final);
  // Adam's steps are at most about the learning rate: 12 of them can cover the 6 cm; within 2 cm
  // of the truth takes a gradient of the right sign and size all the way (lavapipe: 0.0052).
  EXPECT_LT(std::abs(final), 0.02);
  EXPECT_FALSE(fs::exists(dir / "run" / "scene.json")) << "an XML scene is not rewritten as JSON";
}

}  // namespace
}  // namespace vktg
