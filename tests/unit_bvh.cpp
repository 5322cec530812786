// BVH build and CPU traversal: traversal must equal brute force bit for bit (same triangle, same
// t, u, v) on random and adversarial soups, and the tree must be structurally sound.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "support/hit_distance_reference.h"
#include "vktg/bvh.h"
#include "vktg/error.h"

namespace vktg {
namespace {

using Soup = std::vector<BvhTriangle>;

struct Ray {
  glm::vec3 origin, dir;
  float tMin, tMax;
};

uint32_t word(float f) { return std::bit_cast<uint32_t>(f); }
uint32_t nodeCount(const gpu::GpuBvhNode& n) { return word(n.rightMinCount.w); }
uint32_t nodeFirst(const gpu::GpuBvhNode& n) { return word(n.rightMaxFirst.w); }
uint32_t nodeLeft(const gpu::GpuBvhNode& n) { return word(n.leftMinLeftIndex.w); }
uint32_t nodeRight(const gpu::GpuBvhNode& n) { return word(n.leftMaxRightIndex.w); }

Soup leafOrder(const Soup& soup, const Bvh& bvh) {
  Soup out(bvh.order.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = soup[bvh.order[i]];
  return out;
}

glm::vec3 randomVec(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

Soup randomSoup(std::mt19937& rng, size_t n, float extent, float size) {
  Soup soup(n);
  for (BvhTriangle& t : soup) {
    glm::vec3 c = randomVec(rng, -extent, extent);
    t = {c + randomVec(rng, -size, size), c + randomVec(rng, -size, size), c + randomVec(rng, -size, size)};
  }
  return soup;
}

// Mixed rays: random origins around the scene (many inside node boxes), random directions,
// axis-parallel directions with exact (and negative) zeros, aimed rays through random vertices
// (edge/vertex hits), random [tMin, tMax] windows.
std::vector<Ray> randomRays(std::mt19937& rng, const Soup& soup, size_t n, float extent) {
  std::vector<Ray> rays;
  std::uniform_int_distribution<size_t> pick(0, soup.size() - 1);
  std::uniform_int_distribution<int> kind(0, 5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (size_t i = 0; i < n; ++i) {
    Ray r{randomVec(rng, -1.5f * extent, 1.5f * extent), randomVec(rng, -1.0f, 1.0f), 0.0f, INFINITY};
    switch (kind(rng)) {
      case 0: {  // axis-parallel, zeros signed both ways
        int axis = static_cast<int>(unit(rng) * 3.0f) % 3;
        r.dir = glm::vec3(unit(rng) < 0.5f ? 0.0f : -0.0f);
        r.dir[axis] = unit(rng) < 0.5f ? 1.0f : -1.0f;
        break;
      }
      case 1: {  // aimed at a vertex or an edge midpoint
        const BvhTriangle& t = soup[pick(rng)];
        glm::vec3 target = unit(rng) < 0.5f ? t.p1 : 0.5f * (t.p0 + t.p2);
        r.dir = target - r.origin;
        break;
      }
      case 2: {  // aimed at a triangle interior, with a window around the hit
        const BvhTriangle& t = soup[pick(rng)];
        float a = unit(rng), b = unit(rng) * (1.0f - a);
        r.dir = t.p0 + a * (t.p1 - t.p0) + b * (t.p2 - t.p0) - r.origin;
        r.tMin = 0.3f * unit(rng);
        r.tMax = 0.7f + unit(rng);
        break;
      }
      case 3:  // zero in one component only
        r.dir[static_cast<int>(unit(rng) * 3.0f) % 3] = 0.0f;
        break;
      default:
        break;
    }
    rays.push_back(r);
  }
  return rays;
}

struct CompareStats {
  size_t rays = 0, hits = 0;
};

// Traversal vs brute force; returns counts so callers can require non-trivial coverage.
CompareStats expectTraversalMatches(const Bvh& bvh, const Soup& ordered, const std::vector<Ray>& rays) {
  CompareStats stats;
  for (const Ray& r : rays) {
    std::optional<RayHit> ref = traceClosestBruteForce(ordered, r.origin, r.dir, r.tMin, r.tMax);
    std::optional<RayHit> got = traceClosest(bvh, ordered, r.origin, r.dir, r.tMin, r.tMax);
    bool any = traceAny(bvh, ordered, r.origin, r.dir, r.tMin, r.tMax);
    ++stats.rays;
    std::ostringstream where;
    where << "origin " << r.origin.x << " " << r.origin.y << " " << r.origin.z << " dir " << r.dir.x << " "
          << r.dir.y << " " << r.dir.z << " t [" << r.tMin << ", " << r.tMax << "]";
    EXPECT_EQ(any, ref.has_value()) << where.str();
    if (!ref) {
      EXPECT_FALSE(got.has_value()) << where.str();
      continue;
    }
    ++stats.hits;
    if (!got) {
      ADD_FAILURE() << "traversal missed triangle " << ref->triangle << " at t " << ref->t << ": " << where.str();
      continue;
    }
    EXPECT_EQ(got->triangle, ref->triangle) << where.str();
    EXPECT_EQ(word(got->t), word(ref->t)) << where.str();
    EXPECT_EQ(word(got->u), word(ref->u)) << where.str();
    EXPECT_EQ(word(got->v), word(ref->v)) << where.str();
  }
  return stats;
}

// Structure: `order` is a permutation, every node reached once, every stored child box contains
// the vertices of its subtree, leaves respect maxLeafSize unless their centroids coincide.
// Returns the depth of the deepest leaf.
uint32_t expectSoundStructure(const Bvh& bvh, const Soup& soup, const BvhBuildOptions& options = {}) {
  std::vector<int> seen(soup.size(), 0);
  for (uint32_t i : bvh.order) {
    EXPECT_LT(i, soup.size());
    if (i < soup.size()) ++seen[i];
  }
  EXPECT_EQ(bvh.order.size(), soup.size());
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "triangle " << i;
  if (soup.empty()) return 0;

  Soup ordered = leafOrder(soup, bvh);
  std::vector<int> visits(bvh.nodes.size(), 0);
  std::vector<int> covered(soup.size(), 0);
  uint32_t maxDepth = 0;
  // Returns the [first, end) leaf-order range below `node`; leaf ranges are contiguous.
  std::function<std::pair<uint32_t, uint32_t>(uint32_t, uint32_t)> walk = [&](uint32_t node, uint32_t depth) {
    EXPECT_LT(node, bvh.nodes.size());
    if (node >= bvh.nodes.size()) return std::pair<uint32_t, uint32_t>{0, 0};
    ++visits[node];
    maxDepth = std::max(maxDepth, depth);
    const gpu::GpuBvhNode& n = bvh.nodes[node];
    if (nodeCount(n) > 0) {
      uint32_t first = nodeFirst(n), count = nodeCount(n);
      EXPECT_LE(first + count, soup.size());
      for (uint32_t i = first; i < std::min<uint32_t>(first + count, soup.size()); ++i) ++covered[i];
      if (count > options.maxLeafSize) {
        // Only a leaf whose triangles share one centroid (box centre) may exceed maxLeafSize.
        glm::vec3 lo, hi;
        auto centre = [&](uint32_t i) {
          lo = glm::min(glm::min(ordered[i].p0, ordered[i].p1), ordered[i].p2);
          hi = glm::max(glm::max(ordered[i].p0, ordered[i].p1), ordered[i].p2);
          return 0.5f * (lo + hi);
        };
        glm::vec3 c0 = centre(first);
        float spread = 0.0f;
        for (uint32_t i = first; i < first + count; ++i) spread = std::max(spread, glm::length(centre(i) - c0));
        EXPECT_LE(spread, 1e-5f * (1.0f + glm::length(c0))) << "leaf of " << count << " triangles whose centroids differ";
      }
      return std::pair<uint32_t, uint32_t>{first, first + count};
    }
    auto left = walk(nodeLeft(n), depth + 1);
    auto right = walk(nodeRight(n), depth + 1);
    EXPECT_EQ(left.second, right.first) << "children's leaf ranges are not adjacent";
    auto contains = [&](glm::vec3 lo, glm::vec3 hi, std::pair<uint32_t, uint32_t> range) {
      for (uint32_t i = range.first; i < range.second; ++i)
        for (glm::vec3 p : {ordered[i].p0, ordered[i].p1, ordered[i].p2})
          EXPECT_TRUE(glm::all(glm::lessThanEqual(lo, p)) && glm::all(glm::lessThanEqual(p, hi)))
              << "node " << node << " box does not contain triangle " << i;
    };
    contains(glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex), left);
    contains(glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst), right);
    return std::pair<uint32_t, uint32_t>{left.first, right.second};
  };
  auto all = walk(0, 0);
  EXPECT_EQ(all.first, 0u);
  EXPECT_EQ(all.second, soup.size());
  for (size_t i = 0; i < visits.size(); ++i) EXPECT_EQ(visits[i], 1) << "node " << i;
  for (size_t i = 0; i < covered.size(); ++i) EXPECT_EQ(covered[i], 1) << "leaf-order slot " << i;
  EXPECT_LE(maxDepth, options.maxDepth);
  return maxDepth;
}

void checkSoup(const Soup& soup, const std::vector<Ray>& rays, double minHitFraction) {
  Bvh bvh = buildBvh(soup);
  expectSoundStructure(bvh, soup);
  CompareStats stats = expectTraversalMatches(bvh, leafOrder(soup, bvh), rays);
  EXPECT_GE(static_cast<double>(stats.hits), minHitFraction * static_cast<double>(stats.rays))
      << "too few hits for the comparison to mean anything";
}

TEST(IntersectTriangle, KnownHitAndBarycentrics) {
  BvhTriangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  auto hit = intersectTriangle(tri, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 0.0f, INFINITY);
  ASSERT_TRUE(hit);
  EXPECT_FLOAT_EQ(hit->t, 2.0f);
  EXPECT_FLOAT_EQ(hit->u, 0.25f);  // weight of p1 (x)
  EXPECT_FLOAT_EQ(hit->v, 0.5f);   // weight of p2 (y)
  // Back face is hit too.
  auto back = intersectTriangle(tri, {0.25f, 0.5f, -3.0f}, {0, 0, 2}, 0.0f, INFINITY);
  ASSERT_TRUE(back);
  EXPECT_FLOAT_EQ(back->t, 1.5f);
  // The window is open on both ends.
  EXPECT_FALSE(intersectTriangle(tri, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 2.0f, INFINITY));
  EXPECT_FALSE(intersectTriangle(tri, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 0.0f, 2.0f));
  EXPECT_TRUE(intersectTriangle(tri, {0.25f, 0.5f, 2.0f}, {0, 0, -1}, 1.999f, 2.001f));
  // Outside the triangle, and a ray in the triangle's plane.
  EXPECT_FALSE(intersectTriangle(tri, {0.75f, 0.5f, 2.0f}, {0, 0, -1}, 0.0f, INFINITY));
  EXPECT_FALSE(intersectTriangle(tri, {-1.0f, 0.25f, 0.0f}, {1, 0, 0}, 0.0f, INFINITY));
}

TEST(IntersectTriangle, ScaleInvariantDeterminantTest) {
  // A 1e-4 triangle must be hit as well as a 1e4 one: the determinant threshold is relative.
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    BvhTriangle tri{glm::vec3(0, 0, 0) * scale, glm::vec3(1, 0, 0) * scale, glm::vec3(0, 1, 0) * scale};
    auto hit = intersectTriangle(tri, glm::vec3(0.2f, 0.2f, 1.0f) * scale, {0, 0, -1}, 0.0f, INFINITY);
    ASSERT_TRUE(hit) << scale;
    EXPECT_NEAR(hit->t, scale, 1e-6f * scale);
  }
}

TEST(IntersectTriangle, DegenerateTrianglesMiss) {
  glm::vec3 p{0.3f, 0.1f, 0.0f};
  EXPECT_FALSE(intersectTriangle({p, p, p}, {0.3f, 0.1f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY));
  EXPECT_FALSE(intersectTriangle({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}}, {0.5f, 0.5f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY));
}

TEST(IntersectTriangle, WatertightAtSharedEdgesAndVertices) {
  // A tilted, bumpy grid of quads split in two: rays aimed exactly at its vertices (shared by up
  // to six triangles) and at points of its shared edges must hit at least one triangle each. The
  // edge functions of a shared edge are exact negatives, so no ray slips between two triangles.
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const int n = 12;
  std::vector<glm::vec3> grid;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) grid.push_back({0.37f * i + 0.11f * j, 0.05f * unit(rng) + 0.13f * i, 0.41f * j});
  Soup soup;
  auto at = [&](int i, int j) { return grid[size_t(j * (n + 1) + i)]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      soup.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      soup.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  size_t rays = 0, misses = 0;
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i)
      for (int k = 0; k < 6; ++k) {
        glm::vec3 target = k == 0 ? at(i, j)
                           : k < 3 ? at(i, j) + unit(rng) * (at(i + 1, j + 1) - at(i, j))  // diagonal edge
                                   : at(i, j) + unit(rng) * (at(i + 1, j) - at(i, j));      // grid edge
        glm::vec3 origin = target + glm::vec3(4.0f * unit(rng) - 2.0f, 1.0f + 3.0f * unit(rng), 4.0f * unit(rng) - 2.0f);
        ++rays;
        if (!traceClosestBruteForce(soup, origin, target - origin, 0.0f, INFINITY)) ++misses;
      }
  EXPECT_EQ(misses, 0u) << "of " << rays << " rays through shared edges and vertices";
}

TEST(IntersectTriangle, RefinedHitDistanceWithinOneUlp) {
  // Hit distances against the exact distance to the plane (long double): triangles 10^4 times
  // larger than the distance to the hit (where the test's own t is off by 10^-4 relative),
  // slivers, and grazing rays down to 1e-5 rad. docs/precision.md states the bound.
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Soup soup;
  for (int i = 0; i < 200; ++i) {
    glm::vec3 c = randomVec(rng, -4.0f, 4.0f), axis = glm::normalize(randomVec(rng, -1.0f, 1.0f));
    glm::vec3 side = glm::normalize(glm::cross(axis, randomVec(rng, -1.0f, 1.0f)));
    float size = i % 2 ? 1e4f : 6.0f;
    float width = i % 2 ? size : 1e-3f;
    soup.push_back({c - size * axis, c + size * axis + width * side, c - width * side});
  }
  double worstUlps = 0, worstSteepUlps = 0, worstRatio = 0;
  size_t hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const BvhTriangle& t = soup[size_t(i) % soup.size()];
    glm::vec3 n = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
    glm::vec3 target = t.p0 + 0.3f * unit(rng) * (t.p1 - t.p0) + 0.3f * unit(rng) * (t.p2 - t.p0);
    glm::vec3 inPlane = glm::normalize(glm::cross(n, randomVec(rng, -1.0f, 1.0f)));
    float grazing = i % 2 ? std::pow(10.0f, -1.0f - 4.0f * unit(rng)) : 0.3f + unit(rng);
    glm::vec3 dir = glm::normalize(std::cos(grazing) * inPlane - std::sin(grazing) * n);
    glm::vec3 origin = target - (0.5f + 10.0f * unit(rng)) * dir;
    std::optional<RayHit> hit = intersectTriangle(t, origin, dir, 0.0f, INFINITY);
    if (!hit) continue;
    ++hits;
    double ulps = test::hitDistanceErrorUlps(hit->t, test::exactHitDistance(t, origin, dir));
    worstUlps = std::max(worstUlps, ulps);
    if (i % 2 == 0) worstSteepUlps = std::max(worstSteepUlps, ulps);
    double ratio = test::hitDistanceErrorRatio(hit->t, t, origin, dir);
    worstRatio = std::max(worstRatio, ratio);
    ASSERT_LE(ratio, 1.0) << "ray " << i << ": t " << hit->t;
  }
  EXPECT_GT(hits, 15000u);
  // Where the ray meets the plane at 0.3 rad or more the bound is about an ulp, whatever the size.
  EXPECT_LE(worstSteepUlps, test::kHitDistanceUlps);
  std::printf("  %zu hits: refined hit distance within %.3f ulp of exact at >= 0.3 rad, %.3g ulp at grazing "
              "angles down to 1e-5 rad; at most %.3f of the bound\n",
              hits, worstSteepUlps, worstUlps, worstRatio);
}

TEST(BvhBuild, SingleTriangleIsRootLeaf) {
  Soup soup{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  Bvh bvh = buildBvh(soup);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(nodeCount(bvh.nodes[0]), 1u);
  EXPECT_EQ(nodeFirst(bvh.nodes[0]), 0u);
  auto hit = traceClosest(bvh, soup, {0.2f, 0.2f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->triangle, 0u);
  EXPECT_FALSE(traceClosest(bvh, soup, {2.0f, 2.0f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY));
}

TEST(BvhBuild, EmptySceneMissesEverything) {
  Soup soup;
  Bvh bvh = buildBvh(soup);
  ASSERT_FALSE(bvh.nodes.empty());
  EXPECT_FALSE(traceClosest(bvh, soup, {0, 0, 0}, {0, 0, 1}, 0.0f, INFINITY));
  EXPECT_FALSE(traceAny(bvh, soup, {0, 0, 0}, {1, 0, 0}, 0.0f, INFINITY));
}

TEST(BvhBuild, RejectsBadOptions) {
  Soup soup{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  BvhBuildOptions o;
  o.maxLeafSize = 0;
  EXPECT_THROW(buildBvh(soup, o), Error);
  o = {};
  o.maxDepth = kBvhStackSize + 1;
  EXPECT_THROW(buildBvh(soup, o), Error);
}

TEST(BvhBuild, Deterministic) {
  std::mt19937 rng(7);
  Soup soup = randomSoup(rng, 3000, 10.0f, 0.5f);
  Bvh a = buildBvh(soup), b = buildBvh(soup);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(gpu::GpuBvhNode)), 0);
}

TEST(BvhBuild, HundredThousandTrianglesBuildSound) {
  // The build's speed is a benchmark (`vktg bench bvh`), not a unit test.
  std::mt19937 rng(11);
  Soup soup = randomSoup(rng, 100000, 50.0f, 0.3f);
  Bvh bvh = buildBvh(soup);
  expectSoundStructure(bvh, soup);
}

// The SAH cost of a moved scene's tree, computed without a refit copy, is that of the refit copy to
// the last bit (an optimisation rebuilds when it passes a threshold, so a resumed run must see the
// same value). Small and large soups, a lone leaf, and motion large enough to change the cost.
TEST(BvhRefit, SahCostWithoutACopyEqualsTheRefitTreesCost) {
  std::mt19937 rng(29);
  for (size_t n : {1, 3, 40, 5000}) {
    SCOPED_TRACE("triangles: " + std::to_string(n));
    const Soup soup = randomSoup(rng, n, 10.0f, 0.5f);
    const Bvh bvh = buildBvh(soup);
    Soup moved = leafOrder(soup, bvh);
    for (BvhTriangle& t : moved) {
      const glm::vec3 shift = randomVec(rng, -1.0f, 1.0f);
      t.p0 += shift;
      t.p1 += shift + randomVec(rng, -0.2f, 0.2f);
      t.p2 += shift;
    }
    Bvh refit = bvh;
    refitBvh(refit, moved);
    EXPECT_EQ(refitSahCost(bvh, moved), bvhSahCost(refit));
    EXPECT_EQ(refitSahCost(bvh, moved, 0.3f), bvhSahCost(refit, 0.3f));
    if (n > 1) EXPECT_NE(refitSahCost(bvh, moved), bvhSahCost(bvh));
    EXPECT_EQ(refitSahCost(bvh, leafOrder(soup, bvh)), bvhSahCost(bvh));
  }
}

TEST(BvhTraversal, RandomSoupsMatchBruteForce) {
  std::mt19937 rng(1234);
  for (size_t n : {1, 2, 3, 5, 17, 100, 1000, 5000}) {
    SCOPED_TRACE("triangles: " + std::to_string(n));
    Soup soup = randomSoup(rng, n, 5.0f, n < 50 ? 2.0f : 0.6f);
    checkSoup(soup, randomRays(rng, soup, n >= 1000 ? 4000 : 1500, 5.0f), n < 50 ? 0.1 : 0.2);
  }
}

TEST(BvhTraversal, LeafSizesAndBinCountsMatchBruteForce) {
  std::mt19937 rng(99);
  Soup soup = randomSoup(rng, 2000, 4.0f, 0.5f);
  std::vector<Ray> rays = randomRays(rng, soup, 2000, 4.0f);
  for (uint32_t leaf : {1u, 2u, 8u}) {
    for (uint32_t bins : {2u, 16u, 32u}) {
      BvhBuildOptions o;
      o.maxLeafSize = leaf;
      o.bins = bins;
      Bvh bvh = buildBvh(soup, o);
      expectSoundStructure(bvh, soup, o);
      expectTraversalMatches(bvh, leafOrder(soup, bvh), rays);
    }
  }
}

TEST(BvhAdversarial, AllTrianglesCoincident) {
  Soup soup(300, BvhTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  Bvh bvh = buildBvh(soup);
  EXPECT_EQ(nodeCount(bvh.nodes[0]), 300u) << "coincident centroids must make one leaf";
  std::mt19937 rng(5);
  auto stats = expectTraversalMatches(bvh, leafOrder(soup, bvh), randomRays(rng, soup, 2000, 1.0f));
  EXPECT_GT(stats.hits, 200u);
  // The tie goes to the smallest leaf-order index.
  auto hit = traceClosest(bvh, leafOrder(soup, bvh), {0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, INFINITY);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->triangle, 0u);
}

TEST(BvhAdversarial, ManyCoincidentVertices) {
  std::mt19937 rng(6);
  std::vector<glm::vec3> pool;
  for (int i = 0; i < 12; ++i) pool.push_back(randomVec(rng, -1.0f, 1.0f));
  std::uniform_int_distribution<size_t> pick(0, pool.size() - 1);
  Soup soup(2000);
  for (BvhTriangle& t : soup) t = {pool[pick(rng)], pool[pick(rng)], pool[pick(rng)]};
  checkSoup(soup, randomRays(rng, soup, 3000, 1.0f), 0.2);
}

TEST(BvhAdversarial, ThinLongSlivers) {
  std::mt19937 rng(8);
  Soup soup;
  for (int i = 0; i < 1500; ++i) {
    glm::vec3 a = randomVec(rng, -5.0f, 5.0f);
    glm::vec3 axis = glm::normalize(randomVec(rng, -1.0f, 1.0f));
    glm::vec3 side = glm::normalize(glm::cross(axis, randomVec(rng, -1.0f, 1.0f))) * 1e-4f;
    soup.push_back({a, a + 10.0f * axis, a + 5.0f * axis + side});
  }
  // Rays aimed at the slivers, so many actually hit them.
  std::vector<Ray> rays = randomRays(rng, soup, 3000, 5.0f);
  for (size_t i = 0; i < 2000; ++i) {
    const BvhTriangle& t = soup[i % soup.size()];
    glm::vec3 target = t.p0 + 0.3f * (t.p1 - t.p0) + 0.5f * (t.p2 - t.p0) * 0.5f;
    glm::vec3 o = randomVec(rng, -8.0f, 8.0f);
    rays.push_back({o, target - o, 0.0f, INFINITY});
  }
  checkSoup(soup, rays, 0.2);
}

TEST(BvhAdversarial, AxisAlignedFlatScenes) {
  // A grid of unit quads in z = 0.5 plus walls in x = const: flat boxes, shared edges, and rays
  // along the axes through vertices and edges, some lying in the plane itself.
  Soup soup;
  for (int i = -6; i < 6; ++i)
    for (int j = -6; j < 6; ++j) {
      glm::vec3 a(i, j, 0.5f), b(i + 1, j, 0.5f), c(i + 1, j + 1, 0.5f), d(i, j + 1, 0.5f);
      soup.push_back({a, b, c});
      soup.push_back({a, c, d});
    }
  for (int k = -2; k <= 2; ++k)
    for (int j = -3; j < 3; ++j) {
      glm::vec3 a(k * 2.0f, j, -1), b(k * 2.0f, j + 1, -1), c(k * 2.0f, j + 1, 1), d(k * 2.0f, j, 1);
      soup.push_back({a, b, c});
      soup.push_back({a, c, d});
    }
  std::vector<Ray> rays;
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> grid(-7, 7);
  std::uniform_int_distribution<int> axis(0, 2);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 4000; ++i) {
    glm::vec3 o(grid(rng) * 0.5f, grid(rng) * 0.5f, grid(rng) * 0.25f);
    if (i % 4 == 0) o.z = 0.5f;  // in the grid's plane
    glm::vec3 d(0.0f);
    int a = axis(rng);
    d[a] = unit(rng) < 0.5f ? -1.0f : 1.0f;
    if (i % 3 == 0) d[(a + 1) % 3] = unit(rng) < 0.5f ? 0.5f : -0.0f;
    rays.push_back({o, d, 0.0f, INFINITY});
  }
  for (const Ray& r : randomRays(rng, soup, 2000, 6.0f)) rays.push_back(r);
  checkSoup(soup, rays, 0.2);
}

TEST(BvhAdversarial, HugeAndTinyTrianglesMixed) {
  std::mt19937 rng(10);
  Soup soup;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 3000; ++i) {
    float size = unit(rng) < 0.5f ? 1e-4f : 1e4f;
    glm::vec3 c = randomVec(rng, -10.0f, 10.0f);
    soup.push_back({c + randomVec(rng, -size, size), c + randomVec(rng, -size, size), c + randomVec(rng, -size, size)});
  }
  std::vector<Ray> rays = randomRays(rng, soup, 4000, 10.0f);
  checkSoup(soup, rays, 0.2);
  // Rays aimed at the tiny ones specifically.
  std::vector<Ray> tiny;
  for (size_t i = 0; i < soup.size() && tiny.size() < 2000; ++i) {
    const BvhTriangle& t = soup[i];
    if (glm::length(t.p1 - t.p0) > 1.0f) continue;
    glm::vec3 o = randomVec(rng, -20.0f, 20.0f);
    tiny.push_back({o, (t.p0 + t.p1 + t.p2) / 3.0f - o, 0.0f, INFINITY});
  }
  Bvh bvh = buildBvh(soup);
  expectTraversalMatches(bvh, leafOrder(soup, bvh), tiny);
}

TEST(BvhAdversarial, GrazingRaysAlongTrianglePlanes) {
  std::mt19937 rng(12);
  Soup soup = randomSoup(rng, 1500, 3.0f, 0.8f);
  std::uniform_int_distribution<size_t> pick(0, soup.size() - 1);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 6000; ++i) {
    const BvhTriangle& t = soup[pick(rng)];
    glm::vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, n = glm::cross(e1, e2);
    glm::vec3 inPlane = unit(rng) * e1 + unit(rng) * e2;
    // Origin in (or near) the plane, direction in the plane or tilted by up to 1e-2 rad.
    float tilt = std::pow(10.0f, -2.0f - 6.0f * std::abs(unit(rng)));
    if (i % 5 == 0) tilt = 0.0f;
    glm::vec3 dir = glm::normalize(inPlane) + tilt * glm::normalize(n) * (unit(rng) < 0 ? -1.0f : 1.0f);
    glm::vec3 origin = t.p0 + 2.0f * unit(rng) * e1 + 2.0f * unit(rng) * e2 - 3.0f * dir;
    rays.push_back({origin, dir, 0.0f, INFINITY});
  }
  checkSoup(soup, rays, 0.05);
}

TEST(BvhAdversarial, NearlyGrazingRaysLeavingTriangleEdges) {
  // The hardest case for box culling: a ray almost in a triangle's plane, starting just outside
  // the triangle's box and moving away from it. The true crossing is behind the origin, but the
  // test's t for such rays can be off by more than the box padding, so it may report t > 0 while
  // the box lies entirely behind the ray. Traversal must still agree with brute force.
  std::mt19937 rng(14);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Soup soup = randomSoup(rng, 400, 4.0f, 3.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 20000; ++i) {
    const BvhTriangle& t = soup[i % soup.size()];
    glm::vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, n = glm::normalize(glm::cross(e1, e2));
    // A point on edge p1-p2 (or a vertex), pushed out of the triangle within its plane.
    float a = unit(rng) < 0.3f ? 0.0f : unit(rng);
    glm::vec3 edgePoint = t.p1 + a * (t.p2 - t.p1);
    glm::vec3 outward = glm::normalize(edgePoint - (t.p0 + t.p1 + t.p2) / 3.0f);
    float tilt = std::pow(10.0f, -3.0f - 3.5f * unit(rng)) * (unit(rng) < 0.5f ? -1.0f : 1.0f);
    glm::vec3 dir = outward + tilt * n;
    float gap = std::pow(10.0f, -5.0f - 2.0f * unit(rng)) * glm::length(e1);
    rays.push_back({edgePoint + gap * outward, dir, 0.0f, INFINITY});
    rays.push_back({edgePoint + gap * outward + 2.0f * dir, -dir, 0.0f, 2.0f});
  }
  checkSoup(soup, rays, 0.0);
}

TEST(BvhAdversarial, RaysStartingInsideBoxesWithWindows) {
  std::mt19937 rng(13);
  Soup soup = randomSoup(rng, 4000, 2.0f, 0.3f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 4000; ++i) {
    // Origins on triangles (like secondary rays), tMin a small epsilon or zero.
    const BvhTriangle& t = soup[i % soup.size()];
    float a = unit(rng), b = unit(rng) * (1.0f - a);
    glm::vec3 o = t.p0 + a * (t.p1 - t.p0) + b * (t.p2 - t.p0);
    float tMin = i % 2 == 0 ? 0.0f : 1e-4f;
    float tMax = i % 3 == 0 ? 0.5f + unit(rng) : INFINITY;
    rays.push_back({o, randomVec(rng, -1.0f, 1.0f), tMin, tMax});
  }
  checkSoup(soup, rays, 0.2);
}

// SAH cost of a tree: node visits weighted by surface area relative to the root.
double boxArea(glm::vec3 lo, glm::vec3 hi) {
  glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

void triangleBox(const BvhTriangle& t, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::min(glm::min(t.p0, t.p1), t.p2);
  hi = glm::max(glm::max(t.p0, t.p1), t.p2);
}

double sahCostOf(const Bvh& bvh) {
  // Sum over children boxes stored in interior nodes: interior child -> traversal cost 1,
  // leaf child -> its triangle count. The root's own visit is common to every tree.
  double cost = 0.0;
  std::function<void(uint32_t, double)> walk = [&](uint32_t node, double area) {
    const gpu::GpuBvhNode& n = bvh.nodes[node];
    if (nodeCount(n) > 0) {
      cost += area * nodeCount(n);
      return;
    }
    cost += area;
    walk(nodeLeft(n), boxArea(glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex)));
    walk(nodeRight(n), boxArea(glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst)));
  };
  walk(0, 1.0);
  return cost;
}

// The same cost for an object-median tree (largest centroid axis), as the baseline.
double medianCost(const Soup& soup, uint32_t maxLeaf) {
  std::vector<uint32_t> idx(soup.size());
  for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::function<double(size_t, size_t, double)> rec = [&](size_t b, size_t e, double area) -> double {
    if (e - b <= maxLeaf) return area * static_cast<double>(e - b);
    glm::vec3 clo(INFINITY), chi(-INFINITY);
    for (size_t i = b; i < e; ++i) {
      glm::vec3 c = soup[idx[i]].p0 + soup[idx[i]].p1 + soup[idx[i]].p2;
      clo = glm::min(clo, c);
      chi = glm::max(chi, c);
    }
    glm::vec3 ext = chi - clo;
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    size_t m = b + (e - b) / 2;
    std::nth_element(idx.begin() + b, idx.begin() + m, idx.begin() + e, [&](uint32_t x, uint32_t y) {
      return (soup[x].p0 + soup[x].p1 + soup[x].p2)[axis] < (soup[y].p0 + soup[y].p1 + soup[y].p2)[axis];
    });
    auto areaOf = [&](size_t lo, size_t hi) {
      glm::vec3 bl(INFINITY), bh(-INFINITY), tl, th;
      for (size_t i = lo; i < hi; ++i) {
        triangleBox(soup[idx[i]], tl, th);
        bl = glm::min(bl, tl);
        bh = glm::max(bh, th);
      }
      return boxArea(bl, bh);
    };
    double al = areaOf(b, m), ar = areaOf(m, e);
    return area + rec(b, m, al) + rec(m, e, ar);
  };
  glm::vec3 lo(INFINITY), hi(-INFINITY), tl, th;
  for (const BvhTriangle& t : soup) {
    triangleBox(t, tl, th);
    lo = glm::min(lo, tl);
    hi = glm::max(hi, th);
  }
  double root = boxArea(lo, hi);
  // Root visit counted like in sahCostOf (children of the root start the sum).
  return rec(0, soup.size(), root) - root;
}

TEST(BvhBuild, SahBeatsMedianSplitOnClusteredScene) {
  // Three dense clusters of very different populations plus sparse big triangles: a median split
  // cuts through the dense cluster, SAH isolates clusters first.
  std::mt19937 rng(21);
  Soup soup;
  auto cluster = [&](glm::vec3 centre, float radius, float size, int n) {
    for (int i = 0; i < n; ++i) {
      glm::vec3 c = centre + randomVec(rng, -radius, radius);
      soup.push_back({c + randomVec(rng, -size, size), c + randomVec(rng, -size, size), c + randomVec(rng, -size, size)});
    }
  };
  cluster({-20, 0, 0}, 0.5f, 0.05f, 3000);
  cluster({15, 10, 0}, 0.3f, 0.05f, 300);
  cluster({0, -12, 8}, 0.2f, 0.05f, 100);
  cluster({0, 0, 0}, 25.0f, 2.0f, 200);
  Bvh bvh = buildBvh(soup);
  expectSoundStructure(bvh, soup);
  // Normalise by the root box area (same for both trees up to the padding of triangle boxes).
  glm::vec3 lo(INFINITY), hi(-INFINITY), tl, th;
  for (const BvhTriangle& t : soup) {
    triangleBox(t, tl, th);
    lo = glm::min(lo, tl);
    hi = glm::max(hi, th);
  }
  double sah = sahCostOf(bvh) / boxArea(lo, hi);
  double median = medianCost(soup, BvhBuildOptions{}.maxLeafSize) / boxArea(lo, hi);
  std::printf("SAH cost %.2f, median-split cost %.2f\n", sah, median);
  EXPECT_LT(sah, 0.9 * median);
}

TEST(BvhBuild, DepthLimitFallsBackToMedianSplits) {
  // Geometrically spaced triangles invite one-at-a-time SAH splits; a tight maxDepth forces the
  // median fallback, and traversal must still be exact.
  Soup soup;
  for (int i = 0; i < 3000; ++i) {
    float x = std::pow(1.01f, static_cast<float>(i));
    soup.push_back({{x, 0, 0}, {x, 1, 0}, {x, 0, 1}});
  }
  std::mt19937 rng(31);
  std::vector<Ray> rays = randomRays(rng, soup, 2000, 10.0f);
  for (int i = 0; i < 1000; ++i) {
    std::uniform_real_distribution<float> unit(0.01f, 0.4f);
    rays.push_back({{-1.0f, unit(rng), unit(rng)}, {1, 0, 0}, 0.0f, INFINITY});
  }
  for (uint32_t maxDepth : {14u, 20u, kBvhStackSize}) {
    BvhBuildOptions o;
    o.maxDepth = maxDepth;
    Bvh bvh = buildBvh(soup, o);
    uint32_t depth = expectSoundStructure(bvh, soup, o);
    EXPECT_LE(depth, maxDepth);
    expectTraversalMatches(bvh, leafOrder(soup, bvh), rays);
  }
}

TEST(BvhShaders, StackSizeMatchesGlsl) {
  std::ifstream in(std::string(VKTG_SOURCE_DIR) + "/shaders/lib/bvh.glsl");
  ASSERT_TRUE(in) << "shaders/lib/bvh.glsl not found";
  std::stringstream text;
  text << in.rdbuf();
  std::string expected = "const uint kBvhStackSize = " + std::to_string(kBvhStackSize) + "u;";
  EXPECT_NE(text.str().find(expected), std::string::npos) << "bvh.glsl must declare: " << expected;
}

}  // namespace
}  // namespace vktg
