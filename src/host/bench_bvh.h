// `vktg bench bvh`: time to build the BVH of random triangle soups (CPU only): the build's speed
// is a benchmark, not a unit test.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vktg {

struct BvhBenchRow {
  uint32_t triangles = 0;
  double medianSeconds = 0;
  size_t nodes = 0;
};

// Soups of 10^4, 10^5 and 10^6 triangles (fixed seed), each built `runs` times.
std::vector<BvhBenchRow> benchBvhBuild(uint32_t runs);

}  // namespace vktg
