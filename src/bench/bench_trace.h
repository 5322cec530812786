// `vktg bench trace`: how fast the renderer's BVH traversal traces rays on this device, closest hit
// and any hit, for primary (camera) and incoherent (random surface points, uniform directions)
// rays, on a scene file or on the default room with tessellated floors of growing size; and, when
// vktg was built with Embree, the same rays through Embree on the host's cores, measured in the
// same run. Every point traces until a time budget, so it measures the traversal, not launches.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_common.h"
#include "vk/vk_context.h"
#include "vktg/scene.h"

namespace vktg {

struct BenchTraceOptions : BenchOptions {
  std::filesystem::path scene;                   // a scene file; empty: the default room and ...
  SceneDefines defines;                          // a Mitsuba XML scene file's $name values (-D)
  std::vector<uint32_t> sizes = {257, 725};      // ... rooms with n x n heightfields (131k, 1.05M triangles)
  uint32_t rays = 1u << 20;                      // rays per set (times scale, at least 4096)
  double secondsPerPoint = 2.0;                  // trace the set repeatedly until this long (times scale)
  bool embree = true;                            // also through Embree, when built with it
};

struct BenchTraceRow {
  std::string scene;
  uint64_t triangles = 0;
  std::string rays;                // primary, incoherent
  std::string query;               // closest, any
  std::string tree;                // the BVH traversed: "4-wide" or "binary" (GpuScene::wideBvh)
  double raysPerSecond = 0;        // vktg, median over runs
  double embreeRaysPerSecond = 0;  // 0 without Embree
  double hitFraction = 0;          // rays that hit (closest) / are occluded (any)
  uint32_t checked = 0;            // rays compared with the host traversal ...
  uint32_t disagreements = 0;      // ... that disagreed (hit or miss, distance beyond 1e-5 relative)
  uint32_t embreeDisagreements = 0;  // rays whose hit or miss Embree saw otherwise (grazing rays, edges)
};

struct BenchTraceReport {
  std::vector<BenchTraceRow> rows;
  std::string device;
  std::string embree;  // Embree's version; empty when not used
};

BenchTraceReport benchTrace(VulkanContext& context, const BenchTraceOptions& options);
// bench.csv and table.md.
void writeBenchTraceReport(const BenchTraceReport& report, const BenchTraceOptions& options, const std::string& command);

}  // namespace vktg
