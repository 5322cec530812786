// `vktg bench grad`: accuracy versus time of the derivative estimators against the exact
// derivative of the confocal-plane response, and the cost of a gradient relative to the render.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "vk/vk_context.h"

namespace vktg {

using BenchGradOptions = BenchOptions;

struct BenchGradPoint {
  std::string scene, gate, estimator;
  uint32_t spp = 0;
  double seconds = 0, relMse = 0;
};

struct BenchGradReport {
  std::vector<BenchGradPoint> points;
  std::vector<std::string> costLines;  // gradient / primal time at equal samples
  std::string device;
};

BenchGradReport benchGrad(VulkanContext& context, const BenchGradOptions& options);
void writeBenchGradReport(const BenchGradReport& report, const BenchGradOptions& options, const std::string& command);

}  // namespace vktg
