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
constexpr uint32_t kIterations = 30;  // of the documented 60: 40 took 878 s beside the other tests
// Documented outcome at 60 iterations (docs/experiments.md): 0.19 -> 0.003 (seed 5) and 0.026
// (seed 6). The error stays near its start for about 10 iterations, then falls steadily; the
// median of iterations 21-30 is still on that slope: 0.027 with seed 5 (0.034 in this test), 0.078
// with seed 6. Bound: half the start.
constexpr double kBound = 0.5;

TEST(ExperimentHiddenGlass, HiddenRoughGlassPoseRecoveredFromGatedImagesOfTheWalls) {
  test::TempDir dir;
  const test::Recovery r = test::runRecovery(kExperiment / "pose.experiment.json", dir.path() / "pose", kIterations);
  EXPECT_LT(r.end, kBound * r.start);
}

}  // namespace
}  // namespace vktg
