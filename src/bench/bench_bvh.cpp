#include "bench/bench_bvh.h"

#include <algorithm>
#include <chrono>
#include <random>

#include "bench/bench_common.h"
#include "bench/bench_scenes.h"
#include "vktg/bvh.h"
#include "vktg/silhouette_edges.h"

namespace vktg {

std::vector<BvhBenchRow> benchBvhBuild(uint32_t runs) {
  std::vector<BvhBenchRow> rows;
  std::mt19937 rng(11);
  for (uint32_t count : {10000u, 100000u, 1000000u}) {
    // Triangles of about 0.3 m in a 100 m cube: what a scanned room's mesh looks like to the build.
    std::uniform_real_distribution<float> centre(-50.0f, 50.0f), offset(-0.3f, 0.3f);
    std::vector<BvhTriangle> soup(count);
    for (BvhTriangle& t : soup) {
      glm::vec3 c(centre(rng), centre(rng), centre(rng));
      t = {c + glm::vec3(offset(rng), offset(rng), offset(rng)), c + glm::vec3(offset(rng), offset(rng), offset(rng)),
           c + glm::vec3(offset(rng), offset(rng), offset(rng))};
    }
    std::vector<double> seconds;
    BvhBenchRow row;
    row.triangles = count;
    for (uint32_t r = 0; r < std::max(runs, 1u); ++r) {
      auto start = std::chrono::steady_clock::now();
      Bvh bvh = buildBvh(soup);
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      row.nodes = bvh.nodes.size();
    }
    std::nth_element(seconds.begin(), seconds.begin() + seconds.size() / 2, seconds.end());
    row.medianSeconds = seconds[seconds.size() / 2];
    rows.push_back(row);
  }
  return rows;
}

std::vector<EdgeListBenchRow> benchEdgeList(uint32_t runs) {
  std::vector<EdgeListBenchRow> rows;
  for (uint32_t n : {100u, 316u, 1000u}) {
    const PreparedScene prepared = prepareScene(tessellatedRoom(n, 16));
    // The heightfield is the last shape: its n^2 vertices end the list.
    std::vector<bool> displaced(prepared.vertices.size(), false);
    std::fill(displaced.end() - ptrdiff_t(n) * n, displaced.end(), true);
    EdgeListBenchRow row;
    row.vertices = n * n;
    row.triangles = prepared.triangleVerts.size();
    std::vector<double> seconds;
    for (uint32_t r = 0; r < std::max(runs, 1u); ++r) {
      auto start = std::chrono::steady_clock::now();
      row.edges = edgeList(prepared, displaced, displaced).edges.size();
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    row.medianSeconds = median(seconds);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace vktg
