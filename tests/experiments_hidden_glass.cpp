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
constexpr uint32_t kIterations = 40;  // of the documented 60
// Documented outcome at 60 iterations (docs/experiments.md): 0.19 -> 0.003 (seed 5) and 0.017
// (seed 6). Both pass within 6 mm of the truth near iteration 30 and overshoot a little; the median
// of iterations 31-40 was 0.020 (seed 5) and 0.016 (seed 6), so the bound, a quarter of the start, leaves
// a factor 3 for another device's rounding.
constexpr double kBound = 0.25;

TEST(ExperimentHiddenGlass, HiddenRoughGlassPoseRecoveredFromGatedImagesOfTheWalls) {
  test::TempDir dir;
  const std::vector<double> errors =
      test::experimentParameterErrors(kExperiment / "pose.experiment.json", dir.path() / "pose", kIterations);
  const double start = errors.front(), end = test::medianOfLast10(errors);
  std::printf("  parameter error from %.5f: %.5f after %u iterations\n", start, end, kIterations);
  EXPECT_LT(end, kBound * start);
}

}  // namespace
}  // namespace vktg
