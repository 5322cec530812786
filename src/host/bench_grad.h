// `vktg bench grad`: accuracy versus time of the derivative estimators against the exact
// derivative of the confocal-plane response, and the cost of a gradient relative to the render.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "host/vk_context.h"

namespace vktg {

struct BenchGradOptions {
  std::filesystem::path outDir = "runs/bench-grad";
  uint32_t runs = 3;
  uint32_t ladderSteps = 5;
  double scale = 1.0;
  uint64_t memoryBudget = 512ull << 20;
  std::function<void(const std::string&)> log;
};

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
