// `vktg bench nee`: what an ellipsoidal connection costs as the scene's tessellation grows. The
// default room with a bumpy heightfield of n x n vertices on its floor (2 (n-1)^2 triangles), a
// near-delta gaussian gate (sigma / mu = 1e-2), rendered with standard NEE, with ellipsoidal NEE
// choosing triangles by the BVH descent, and (up to a triangle count) by enumeration. Every point
// renders until a time budget and a minimum sample count are reached, so it measures the
// estimator rather than launch overhead; reported: seconds per path and rays per second.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "vk/vk_context.h"

namespace vktg {

struct BenchNeeOptions : BenchOptions {
  std::vector<uint32_t> sizes = {17, 257, 725};  // heightfield vertices per side: 512, 131k, 1.05M triangles
  uint32_t resolution = 64;                      // image width and height (times sqrt(scale))
  double secondsPerPoint = 4.0;                  // render until this much time (times scale)...
  uint64_t minPaths = 4096;                      // ...and at least this many paths
  uint64_t enumerateMaxTriangles = 200000;       // enumeration beyond this takes minutes per point
};

struct BenchNeeRow {
  uint32_t size = 0;
  uint64_t triangles = 0;
  std::string estimator;     // standard, ellipsoidal (descend), ellipsoidal (enumerate)
  double secondsPerPath = 0; // median over runs
  double raysPerSecond = 0;
  double emptyFraction = 0;  // ellipsoidal: connections that found no surface
  double imageMean = 0;      // mean pixel value (the estimators agree on it within noise)
};

struct BenchNeeReport {
  std::vector<BenchNeeRow> rows;
  std::string device;
};

BenchNeeReport benchNee(VulkanContext& context, const BenchNeeOptions& options);
// bench.csv and table.md (per size: cost per path of each estimator and its ratio to standard NEE).
void writeBenchNeeReport(const BenchNeeReport& report, const BenchNeeOptions& options, const std::string& command);

}  // namespace vktg
