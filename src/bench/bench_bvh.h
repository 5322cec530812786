// `vktg bench bvh`: time to build the BVH of random triangle soups, and the silhouette-edge list
// of heightfields (CPU only; what a scene build and every rebuild of a moving scene pay): their
// speed is a benchmark, not a unit test.
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

struct EdgeListBenchRow {
  uint32_t vertices = 0;
  size_t triangles = 0, edges = 0;
  double medianSeconds = 0;
};

// The rooms of tessellatedRoom with heightfields of 10^4, 10^5 and 10^6 vertices, each heightfield
// vertex displaced on its own (as a heightfield's parameters do, so flat creases stay in the list),
// each list made `runs` times.
std::vector<EdgeListBenchRow> benchEdgeList(uint32_t runs);

}  // namespace vktg
