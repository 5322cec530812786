// The hidden rough-glass experiment (experiments/hidden_glass, docs/experiments.md) at reduced
// length: the position (x, y) and rotation of a rough-glass bar that the camera cannot see,
// recovered from 20 gated images of the walls with the image loss only. Asserts the documented
// outcome: the parameter error (RMS over the three parameters, median of the last 10 iterations)
// falls below a stated fraction of the start.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli_runner.h"
#include "support/experiment_run.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

const fs::path kExperiment = fs::path(VKTG_SOURCE_DIR) / "experiments" / "hidden_glass";
constexpr uint32_t kIterations = 60;  // the documented run's length: about 60 s on 2 lavapipe cores
// Documented outcome at 60 iterations (docs/experiments.md): 0.188 -> 0.017 (seed 5, the file's)
// and 0.010 (seed 6), medians of the last 10 iterations. Bound: a quarter of the start.
constexpr double kBound = 0.25;

TEST(ExperimentHiddenGlass, HiddenRoughGlassPoseRecoveredFromGatedImagesOfTheWalls) {
  test::TempDir dir;
  const test::Recovery r = test::runRecovery(kExperiment / "pose.experiment.json", dir.path() / "pose", kIterations);
  EXPECT_LT(r.end, kBound * r.start);
}

}  // namespace
}  // namespace vktg
