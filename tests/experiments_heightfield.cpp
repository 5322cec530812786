// The heightfield experiment (experiments/heightfield, docs/experiments.md) at reduced length:
// 121 heights and the albedo recovered from 12 time-gated images (3 laser positions x 4 gaussian
// gates) and from one steady-state image of the same scene, both starting flat and too dark. Asserts the documented outcome:
// the time-of-flight run's parameter error falls below a stated bound, and the steady run ends
// measurably worse. Errors are medians over the last 10 iterations (Adam oscillates about its
// optimum by about its learning rate).
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli_runner.h"
#include "support/experiment_run.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

const fs::path kExperiment = fs::path(VKTG_SOURCE_DIR) / "experiments" / "heightfield";
constexpr uint32_t kIterations = 60;  // of the documented 150
// Documented outcome at 150 iterations (docs/experiments.md): time of flight 0.053 -> 0.0027;
// steady state 0.053 -> about 0.08 (it moves away: albedo and height trade off in one image).
// At 60 iterations: time of flight below a quarter of the start (measured 0.0101 of 0.053), steady
// state at least 3x worse (measured about 0.083).
constexpr double kTofBound = 0.25, kSteadyRatio = 3.0;

TEST(ExperimentHeightfield, TimeOfFlightRecoversWhatSteadyStateCannot) {
  test::TempDir dir;
  const test::Contrast c = test::runContrast(kExperiment / "tof.experiment.json", kIterations,
                                             kExperiment / "steady.experiment.json", kIterations, dir.path());
  std::printf("  parameter error after %u iterations: time of flight %.5f, steady %.5f (both from %.5f)\n", kIterations,
              c.strong, c.weak, c.start);
  EXPECT_LT(c.strong, kTofBound * c.start);
  EXPECT_GT(c.weak, kSteadyRatio * c.strong);
}

}  // namespace
}  // namespace vktg
