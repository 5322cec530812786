// The confocal NLOS scan (experiments/confocal_scan, docs/experiments.md) at reduced length: 64
// hidden heights recovered from an 8 x 8 scan of transients on a relay wall, starting flat. Asserts
// the documented outcome: the parameter error (RMS over the heights, median of the last 10
// iterations) falls below a stated fraction of the start. The run with 4x wider bins is not run
// here: it ends worse, but by less than the spread of a shortened run. Also that the run draws its
// transients as one scan figure.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli_runner.h"
#include "support/experiment_run.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

const fs::path kExperiment = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan";
constexpr uint32_t kIterations = 60;  // of the documented 150
// Documented outcome at 150 iterations (docs/experiments.md): 0.031 -> 0.0045. At 60 iterations
// below 0.6 of the start (measured 0.0084, the median of iterations 50-59).
constexpr double kBound = 0.6;

TEST(ExperimentConfocalScan, HiddenSurfaceRecoveredFromARelayWallScan) {
  test::TempDir dir;
  const test::Recovery r = test::runRecovery(kExperiment / "fine_bins.experiment.json", dir.path() / "fine", kIterations);
  EXPECT_LT(r.end, kBound * r.start);
  // The 64 transients are drawn together (src/opt/target_figures.h), not one figure per point.
  const fs::path images = dir.path() / "fine" / "images";
  EXPECT_TRUE(fs::exists(images / "transients" / "0.png"));
  EXPECT_TRUE(fs::exists(images / "transients" / (std::to_string(kIterations - 1) + ".png")));
  EXPECT_FALSE(fs::exists(images / "scan_0_0_0.png"));
}

}  // namespace
}  // namespace vktg
