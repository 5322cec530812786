// `vktg bench pilot`: how well the measured-cost NEE choice (host/nee_pilot.h) predicts. Per case
// (scene, gate) the pilot predicts each estimator's time and relMSE for the render; then every
// estimator renders it `runs` times with independent seeds, and the measured relMSE is the
// across-seed variance of each pixel (no reference needed: the estimators are unbiased) over the
// pooled image. Reported: predicted against measured per estimator, the estimator the pilot chose,
// the one the gate-width rule would have chosen, whether `vktg render` would run the whole pilot
// (--pilot auto) or let the rule decide, and what each choice costs against the best measured (its
// regret: measured relMSE x time over the best's).
#pragma once
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "vk/vk_context.h"

namespace vktg {

struct BenchPilotRow {
  std::string scene, gate, estimator;
  uint32_t spp = 0;
  double predictedSeconds = 0, predictedRelMse = 0;
  double measuredSeconds = 0, measuredRelMse = 0;  // median seconds; relMSE from the across-seed variance
  bool excluded = false;                           // the pilot excluded it (its image fell short)
};

struct BenchPilotCase {
  std::string scene, gate;
  std::string pilotChoice, ruleChoice, measuredBest;
  double pilotRegret = 1, ruleRegret = 1;  // measured relMSE x time of the choice / of the best
  bool pays = true;                        // `vktg render` (--pilot auto) would run the whole pilot
  double pilotSeconds = 0;                 // wall time of the pilot
};

struct BenchPilotReport {
  std::vector<BenchPilotRow> rows;
  std::vector<BenchPilotCase> cases;
  std::string device;
};

BenchPilotReport benchPilot(VulkanContext& context, const BenchOptions& options);
void writeBenchPilotReport(const BenchPilotReport& report, const BenchOptions& options, const std::string& command);

}  // namespace vktg
