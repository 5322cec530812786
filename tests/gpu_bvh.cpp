// shaders/lib/bvh.glsl (through tests/shaders/bvh_trace.comp) against the CPU traversal of
// src/scene/bvh.cpp, ray by ray, with the bounds of docs/precision.md instead of bit equality:
//  - the same any-hit answer and the same closest triangle. Every decision of the triangle test is
//    made from correctly rounded, uncontracted (`precise`) +, - and *, the host's bits, except the
//    comparisons of t, which divides (2.5 ulp in Vulkan): a GPU may pick another triangle only at
//    a tie, where the CPU finds both within kTieUlps of the same distance;
//  - hit distances within hitDistanceBound (about an ulp) of the exact distance to the chosen
//    triangle's plane, on both sides. The largest error is printed: the measured path-length
//    error of this device.
// Rays through shared edges and vertices are included: the test is watertight on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "support/gpu_test.h"
#include "support/hit_distance_reference.h"
#include "support/scoped_env.h"
#include "vktg/bvh.h"

namespace vktg::test {
namespace {

struct RayIn {
  float origin[3], dir[3], tMin, tMax;
};

struct TraceOut {
  float t, u, v;
  uint32_t triangle, any;
};

glm::vec3 randomVec(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

// A scene whose shapes hold the given triangles (unshared vertices), split over two shapes so
// the concatenation order of the upload is exercised too.
Scene sceneOf(const std::vector<BvhTriangle>& soup) {
  Scene scene;
  scene.materials.push_back({});
  Shape a, b;
  b.emission = 1.0f;
  for (size_t i = 0; i < soup.size(); ++i) {
    Shape& s = i < soup.size() / 2 ? a : b;
    uint32_t base = static_cast<uint32_t>(s.positions.size());
    s.positions.insert(s.positions.end(), {soup[i].p0, soup[i].p1, soup[i].p2});
    s.triangles.push_back({base, base + 1, base + 2});
  }
  if (!a.triangles.empty()) scene.shapes.push_back(a);
  scene.shapes.push_back(b);
  return scene;
}

// A different closest triangle is a tie when the CPU hits it too, within this many ulps of the
// closest distance (the GPU's division may order two equal-looking distances either way).
constexpr double kTieUlps = 4.0;

void expectGpuMatchesCpuWith(const std::vector<BvhTriangle>& soup, const std::vector<RayIn>& rays) {
  Bvh bvh = buildBvh(soup);
  std::vector<BvhTriangle> ordered(soup.size());
  for (size_t i = 0; i < ordered.size(); ++i) ordered[i] = soup[bvh.order[i]];
  Scene scene = sceneOf(soup);
  std::vector<TraceOut> gpuOut =
      runKernel<TraceOut>("bvh_trace", rays, rays.size(), static_cast<uint32_t>(rays.size()), &scene);
  size_t hits = 0, mismatches = 0, ties = 0;
  double worstUlps = 0, worstMetres = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayIn& r = rays[i];
    glm::vec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.dir[0], r.dir[1], r.dir[2]);
    std::optional<RayHit> cpu = traceClosest(bvh, ordered, o, d, r.tMin, r.tMax);
    bool cpuAny = traceAny(bvh, ordered, o, d, r.tMin, r.tMax);
    const TraceOut& g = gpuOut[i];
    bool ok = (g.any != 0) == cpuAny;
    if (cpu) {
      ++hits;
      ok = ok && g.t >= 0.0f && g.triangle < ordered.size();
      if (ok && g.triangle != cpu->triangle) {
        std::optional<RayHit> other = intersectTriangle(ordered[g.triangle], o, d, r.tMin, r.tMax);
        ok = other && std::abs(double(other->t) - double(cpu->t)) <= kTieUlps * floatUlp(cpu->t);
        ties += ok;
      }
      if (ok) {
        long double exact = exactHitDistance(ordered[g.triangle], o, d);
        ok = hitDistanceErrorRatio(g.t, ordered[g.triangle], o, d) <= 1.0 &&
             hitDistanceErrorRatio(cpu->t, ordered[cpu->triangle], o, d) <= 1.0;
        worstUlps = std::max(worstUlps, hitDistanceErrorUlps(g.t, exact));
        worstMetres = std::max(worstMetres, double(std::fabs((long double)g.t - exact)) * double(glm::length(d)));
      }
    } else {
      ok = ok && g.t < 0.0f;
    }
    if (!ok && ++mismatches <= 10) {
      ADD_FAILURE() << "ray " << i << ": gpu (t " << g.t << ", tri " << g.triangle << ", any " << g.any << ") cpu (t " << (cpu ? cpu->t : -1.0f) << ", tri " << (cpu ? cpu->triangle : 0u) << ", any "
                    << cpuAny << ")";
    }
  }
  EXPECT_EQ(mismatches, 0u) << "of " << rays.size() << " rays";
  EXPECT_GE(hits, rays.size() / 5) << "too few hits for the comparison to mean anything";
  std::printf("  %zu rays, %zu hits, %zu ties; hit distance error at most %.3f ulp, %.3g m of path length\n",
              rays.size(), hits, ties, worstUlps, worstMetres);
}

// Both traversals: the binary tree (GPUs) and the 4-wide one (CPU devices, which read the scene
// through texel views; elsewhere both runs take the binary tree).
void expectGpuMatchesCpu(const std::vector<BvhTriangle>& soup, const std::vector<RayIn>& rays) {
  ASSERT_FALSE(collapseBvh(buildBvh(soup)).empty()) << "the wide layout should hold this tree";
  for (const char* width : {"2", "4"}) {
    SCOPED_TRACE(std::string("VKTG_BVH_WIDTH=") + width);
    ScopedEnv env("VKTG_BVH_WIDTH", width);
    expectGpuMatchesCpuWith(soup, rays);
  }
}

RayIn makeRay(glm::vec3 o, glm::vec3 d, float tMin = 0.0f, float tMax = INFINITY) {
  return {{o.x, o.y, o.z}, {d.x, d.y, d.z}, tMin, tMax};
}

TEST(GpuBvh, RandomSoupMatchesCpuTraversal) {
  std::mt19937 rng(42);
  std::vector<BvhTriangle> soup(3000);
  for (BvhTriangle& t : soup) {
    glm::vec3 c = randomVec(rng, -4.0f, 4.0f);
    t = {c + randomVec(rng, -0.5f, 0.5f), c + randomVec(rng, -0.5f, 0.5f), c + randomVec(rng, -0.5f, 0.5f)};
  }
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<RayIn> rays;
  for (int i = 0; i < 4096; ++i) {
    glm::vec3 o = randomVec(rng, -6.0f, 6.0f);
    glm::vec3 d = randomVec(rng, -1.0f, 1.0f);
    if (i % 4 == 0) {  // aimed at a triangle's interior, with a window
      const BvhTriangle& t = soup[i % soup.size()];
      d = t.p0 + 0.3f * (t.p1 - t.p0) + 0.3f * (t.p2 - t.p0) - o;
      rays.push_back(makeRay(o, d, 0.2f * unit(rng), 0.8f + unit(rng)));
      continue;
    }
    rays.push_back(makeRay(o, d));
  }
  expectGpuMatchesCpu(soup, rays);
}

TEST(GpuBvh, AdversarialSoupMatchesCpuTraversal) {
  std::mt19937 rng(43);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<BvhTriangle> soup;
  // Exact duplicates (ties broken by index), an axis-aligned flat grid (flat boxes), slivers,
  // and huge and tiny triangles together.
  for (int i = 0; i < 40; ++i) soup.push_back({{-1, -1, 2}, {1, -1, 2}, {-1, 1, 2}});
  for (int i = -5; i < 5; ++i)
    for (int j = -5; j < 5; ++j) {
      glm::vec3 a(i, j, -1.0f), b(i + 1, j, -1.0f), c(i + 1, j + 1, -1.0f), d(i, j + 1, -1.0f);
      soup.push_back({a, b, c});
      soup.push_back({a, c, d});
    }
  for (int i = 0; i < 300; ++i) {
    glm::vec3 a = randomVec(rng, -4.0f, 4.0f), axis = glm::normalize(randomVec(rng, -1.0f, 1.0f));
    glm::vec3 side = glm::normalize(glm::cross(axis, randomVec(rng, -1.0f, 1.0f))) * 1e-3f;
    soup.push_back({a, a + 6.0f * axis, a + 3.0f * axis + side});
  }
  for (int i = 0; i < 600; ++i) {
    float size = i % 2 ? 1e-4f : 1e4f;
    glm::vec3 c = randomVec(rng, -4.0f, 4.0f);
    soup.push_back({c + randomVec(rng, -size, size), c + randomVec(rng, -size, size), c + randomVec(rng, -size, size)});
  }
  std::vector<RayIn> rays;
  for (int i = 0; i < 4096; ++i) {
    glm::vec3 o = randomVec(rng, -5.0f, 5.0f);
    glm::vec3 d = randomVec(rng, -1.0f, 1.0f);
    switch (i % 4) {
      case 0: {  // axis-parallel with exact (signed) zeros, off the grid lines
        d = glm::vec3(i % 8 == 0 ? 0.0f : -0.0f);
        d[(i / 4) % 3] = (i / 12) % 2 ? 1.0f : -1.0f;
        o = glm::vec3(std::floor(o.x) + 0.37f, std::floor(o.y) + 0.61f, o.z);
        break;
      }
      case 1: {  // aimed at a tiny triangle's interior from afar
        const BvhTriangle& t = soup[soup.size() - 1 - 2 * ((i / 4) % 300)];
        d = (t.p0 + t.p1 + t.p2) / 3.0f - o;
        break;
      }
      case 2:  // one zero component
        d[(i / 4) % 3] = 0.0f;
        break;
      default:  // origin inside the scene's boxes with a window
        rays.push_back(makeRay(o, d, 0.01f, 0.5f + 5.0f * unit(rng)));
        continue;
    }
    rays.push_back(makeRay(o, d));
  }
  expectGpuMatchesCpu(soup, rays);
}

TEST(GpuBvh, GrazingRaysAndFarVerticesMatchCpuTraversal) {
  // A 2e4 m floor of two triangles (its vertices 10^4 times farther than the hits), a fan of
  // triangles around a shared vertex, and rays at grazing angles from 1e-1 down to 1e-5 radians,
  // aimed at the floor, at the fan's shared vertex and at its shared edges.
  std::vector<BvhTriangle> soup{{{-1e4f, 0, -1e4f}, {1e4f, 0, -1e4f}, {1e4f, 0, 1e4f}},
                                {{-1e4f, 0, -1e4f}, {1e4f, 0, 1e4f}, {-1e4f, 0, 1e4f}}};
  const glm::vec3 hub(0.3f, 1.0f, 0.7f);
  for (int k = 0; k < 8; ++k) {
    float a0 = 0.785398f * k, a1 = 0.785398f * (k + 1);
    soup.push_back({hub, hub + glm::vec3(std::cos(a0), 0.2f, std::sin(a0)), hub + glm::vec3(std::cos(a1), 0.2f, std::sin(a1))});
  }
  std::mt19937 rng(45);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<RayIn> rays;
  for (int i = 0; i < 2048; ++i) {
    float grazing = std::pow(10.0f, -1.0f - 4.0f * unit(rng));
    float azimuth = 6.2831853f * unit(rng);
    glm::vec3 target;
    switch (i % 3) {
      case 0: target = glm::vec3(10.0f * unit(rng) - 5.0f, 0.0f, 10.0f * unit(rng) - 5.0f); break;
      case 1: target = hub; break;
      default: {
        const BvhTriangle& t = soup[2 + (i / 3) % 8];
        target = t.p0 + unit(rng) * (t.p1 - t.p0);
      }
    }
    glm::vec3 dir(std::cos(azimuth) * std::cos(grazing), -std::sin(grazing), std::sin(azimuth) * std::cos(grazing));
    if (i % 3 != 0) dir = glm::normalize(glm::vec3(dir.x, -0.5f - unit(rng), dir.z));  // steep onto the fan
    float distance = 1.0f + 9.0f * unit(rng);
    rays.push_back(makeRay(target - distance * dir, dir));
  }
  expectGpuMatchesCpu(soup, rays);
}

TEST(GpuBvh, SingleTriangleRootLeaf) {
  std::vector<BvhTriangle> soup{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  std::vector<RayIn> rays;
  std::mt19937 rng(44);
  for (int i = 0; i < 256; ++i) {
    glm::vec3 target(0.3f * (i % 7) / 7.0f + 0.05f, 0.3f * (i % 5) / 5.0f + 0.05f, 0.0f);
    glm::vec3 o = randomVec(rng, -2.0f, 2.0f);
    rays.push_back(makeRay(o, i % 3 ? target - o : randomVec(rng, -1.0f, 1.0f)));
  }
  expectGpuMatchesCpu(soup, rays);
}

}  // namespace
}  // namespace vktg::test
