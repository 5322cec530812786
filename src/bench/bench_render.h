// `vktg bench render`: accuracy versus time of the forward estimators on named scenes and gates
// (relMSE against an exact or cached high-sample reference), throughput and time per pass.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "vk/vk_context.h"
#include "vktg/scene.h"

namespace vktg {

using BenchRenderOptions = BenchOptions;

struct BenchRenderPoint {
  std::string scene, gate, estimator;
  uint32_t spp = 0;
  double seconds = 0;     // median wall time of the render
  double relMse = 0;      // median relMSE against the reference
  double pathsPerSecond = 0, raysPerSecond = 0;
};

struct BenchRenderReport {
  std::vector<BenchRenderPoint> points;
  std::vector<std::string> passTable;   // time per pass lines of the largest render
  std::string cutoffSummary;            // extension rays with and without the gate cutoff
  double peakDeviceMiB = 0;
  double peakHostMiB = 0;
  std::string device;
};

BenchRenderReport benchRender(VulkanContext& context, const BenchRenderOptions& options);
// Writes bench.csv, the markdown table (table.md) and, through tools/plot_bench.py, plot.png.
void writeBenchRenderReport(const BenchRenderReport& report, const BenchRenderOptions& options, const std::string& command);

// The confocal scene of the benchmark and tests: point sensor and point light at distance h
// before a Lambertian plane, and its exact gated response (THEORY.md-style closed form by quadrature).
Scene confocalPlaneScene(double h, double albedo, double intensity, double halfSize);
double confocalPlaneResponse(double h, double albedo, double intensity, const Gate& gate, double halfSize);

}  // namespace vktg
