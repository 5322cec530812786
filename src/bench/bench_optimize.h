// `vktg bench optimize`: what an optimisation iteration and its loss gradient cost relative to a
// render as the parameter count grows. An n x n heightfield (n^2 height parameters) under a point light is rendered, and the
// gradient of an image loss with respect to every height is taken by the adjoint passes (each
// term alone and all three together) and, for contrast, by forward-mode lanes for a few heights.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "render/device_scene.h"
#include "vk/vk_context.h"

namespace vktg {

struct BenchOptimizeOptions : BenchOptions {
  std::vector<uint32_t> sizes = {11, 100, 1000};  // heightfield vertices per side
  uint32_t resolution = 128;                      // image width and height (times BenchOptions::scale)
  uint32_t spp = 16;                              // of the render and of every gradient term
  bool pathLength = true;                         // false: skip the path-length-boundary term (and "all three")
  bool profile = false;                           // say each pass's device time (last run) for the render and every variant
  // Chained interior passes (host/gradient.h AdjointChain): an iteration whose render takes spp /
  // interiorPasses samples and whose interior term runs in that many passes (1: not measured).
  uint32_t interiorPasses = 4;
  // Every vertex's x, y and z (3 n^2 parameters: free-form geometry, a vertex_positions entry)
  // instead of its height.
  bool positions = false;
};

struct BenchOptimizeRow {
  uint32_t size = 0;              // n
  uint64_t parameters = 0;        // n^2 (heights) or 3 n^2 (positions)
  uint64_t triangles = 0;
  double buildSeconds = 0;        // device scene: prepare, BVH, upload (once)
  double updateSeconds = 0;       // per iteration: move vertices, refit on the device, tables
  double checkSeconds = 0;        // the host's SAH check of the refit tree (every kBvhQualityCheckInterval)
  double renderSeconds = 0;       // the primal render
  double interiorSeconds = 0, edgeSeconds = 0, boundarySeconds = 0, allSeconds = 0;  // adjoint gradients (NaN: skipped)
  double allApartSeconds = 0;  // all terms, the interior and path-length-boundary terms tracing their own paths
  // The term pilot (host/term_pilot.h, `"spp_edge": "auto"` in an experiment): the samples it
  // gives the edge and path-length-boundary terms (the latter's connections from path vertices and
  // from the camera), all terms at those samples, and the variance of that gradient it predicts
  // relative to all terms at the render's samples.
  double pilotSppEdge = 0, pilotSppBoundary = 0, pilotSppBoundaryCamera = 0;
  double pilotAllSeconds = 0, pilotVarianceRatio = 0;
  // At the pilot's samples with the interior term in interiorPasses chained passes: the render of
  // spp / interiorPasses samples and all terms (NaN: not measured).
  double chainedRenderSeconds = 0, pilotChainedSeconds = 0;
  // Its gradient's variance relative to the unchained one's, measured against the bench's target and
  // against a target equal to the image at θ (where an optimisation ends).
  double chainedVarianceRatio = 0, chainedVarianceRatioAtTarget = 0;
  uint32_t denseLanes = 0;        // parameters of the forward-mode contrast
  double denseSeconds = 0;        // their derivative images (all terms)
  // An iteration of `vktg optimize` on the device: update + render + the gradient of every term run
  // (the loss and the optimiser step are host work linear in pixels and parameters, not timed).
  double iterationSeconds(bool pilot = false) const {
    return updateSeconds + checkSeconds / double(kBvhQualityCheckInterval) + renderSeconds +
           (pilot ? pilotAllSeconds : allSeconds);
  }
  // The same at the pilot's samples with chained interior passes (NaN: not measured).
  double chainedIterationSeconds() const {
    return updateSeconds + checkSeconds / double(kBvhQualityCheckInterval) + chainedRenderSeconds + pilotChainedSeconds;
  }
};

struct BenchOptimizeReport {
  std::vector<BenchOptimizeRow> rows;
  std::string device;
};

// `rowDone` (if set) gets the report after each size, so that a run stopped early (a time limit,
// Ctrl-C) can still write the rows it measured.
BenchOptimizeReport benchOptimize(VulkanContext& context, const BenchOptimizeOptions& options,
                                  const std::function<void(const BenchOptimizeReport&)>& rowDone = {});
// bench.csv, table.md and plot.png (cost / render against log10 of the parameter count) in options.outDir.
void writeBenchOptimizeReport(const BenchOptimizeReport& report, const BenchOptimizeOptions& options, const std::string& command);

}  // namespace vktg
