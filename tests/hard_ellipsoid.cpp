// Numerical stability of ellipsoidal connections (THEORY.md §4 hard cases): lengths at and below
// the focal distance, an ellipsoid that has nearly collapsed to a segment, ellipsoids tangent to a
// plane, foci on the surface, and scenes at 1e-3 and 1e3 scale. Outputs must be finite, and mean
// weights must equal d/ds' Area{x : L(x) <= s'} (closed form where there is one, quadrature of
// the surfaces otherwise) within 4.5 measured standard errors plus the reference's own error.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "support/ellipsoid_kernel.h"
#include "support/ellipsoid_reference.h"
#include "support/gpu_test.h"

namespace vktg::test {
namespace {

using SampleIn = EllipsoidSampleIn;
using SampleOut = EllipsoidSampleOut;

constexpr double kPi = std::numbers::pi;
// A weight is assembled from ~100 float32 operations: allow a few hundred ulps of relative error.
const double kFloatRel = 256.0 * std::ldexp(1.0, -24);

// Square [-h, h]^2 at z = 0, scaled by `scale`, as two triangles.
std::vector<RefTriangle> square(double h) {
  return {{{-h, -h, 0}, {h, -h, 0}, {h, h, 0}}, {{-h, -h, 0}, {h, h, 0}, {-h, h, 0}}};
}

Scene makeScene(const std::vector<RefTriangle>& tris) { return sceneOfShapes({shapeOfTriangles("surface", tris)}); }

struct SampleRun {
  std::vector<SampleOut> out;
  double mean = 0.0, se = 0.0;
  size_t hits = 0;
  float s = 0.0f;  // s' as the GPU saw it
};

// Samples n connections for (f1, f2, s') and checks every output is finite and consistent.
SampleRun sample(const Scene& scene, dvec3 f1, dvec3 f2, double s, size_t n, uint32_t seed) {
  const std::vector<SampleIn> in = ellipsoidInputs(n, seed, f1, f2, [&](std::mt19937&) { return float(s); });
  SampleRun run;
  run.s = in[0].s;
  run.out = runKernel<SampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene);
  double sum = 0.0, sq = 0.0;
  for (const SampleOut& o : run.out) {
    const float* fields[] = {o.position, o.bary, &o.weight, &o.density};
    const int sizes[] = {3, 2, 1, 1};
    for (int f = 0; f < 4; ++f)
      for (int k = 0; k < sizes[f]; ++k) EXPECT_TRUE(std::isfinite(fields[f][k]));
    if (!o.ok) {
      EXPECT_EQ(o.weight, 0.0f);
      continue;
    }
    ++run.hits;
    EXPECT_GT(o.weight, 0.0f);
    sum += o.weight;
    sq += double(o.weight) * o.weight;
  }
  run.mean = sum / n;
  run.se = std::sqrt(std::max(sq / n - run.mean * run.mean, 0.0) / (n - 1));
  return run;
}

dvec3 asFloat(dvec3 v) { return dvec3(glm::vec3(v)); }

// Quadrature reference with its error estimate (step halved, rows doubled).
void expectMatchesQuadrature(const std::vector<RefTriangle>& tris, dvec3 f1, dvec3 f2, const SampleRun& run, double h) {
  double s = run.s;
  double coarse = shellAreaDerivative(tris, asFloat(f1), asFloat(f2), s, h, 3000);
  double fine = shellAreaDerivative(tris, asFloat(f1), asFloat(f2), s, 0.5 * h, 6000);
  double tol = 4.5 * run.se + 2.0 * std::abs(fine - coarse) + kFloatRel * fine;
  EXPECT_GT(fine, 0.0);
  EXPECT_NEAR(run.mean, fine, tol) << "se " << run.se << " quadrature error " << std::abs(fine - coarse);
}

TEST(HardEllipsoid, NoSolutionAtOrBelowFocalDistance) {
  auto tris = square(2.0);
  Scene scene = makeScene(tris);
  // Foci on the surface, |f2 - f1| = 2 exactly in float (so the GPU's focal distance is exact
  // too): at s' = 2 the ellipsoid is the segment itself, lying in the plane.
  dvec3 f1(-1.0, 0.0, 0.0), f2(1.0, 0.0, 0.0);
  for (double s : {2.0, 2.0 * (1.0 - 1e-7), 1.0, 0.0, -1.0}) {
    SampleRun run = sample(scene, f1, f2, s, 256, 1);
    EXPECT_EQ(run.hits, 0u) << "s' = " << s;
    for (const SampleOut& o : run.out) EXPECT_EQ(o.density, 0.0f);
  }
  // Coincident foci with s' = 0: a sphere of radius 0.
  SampleRun run = sample(scene, f1, f1, 0.0, 64, 2);
  EXPECT_EQ(run.hits, 0u);
}

TEST(HardEllipsoid, NearlySegmentInThePlane) {
  // Foci on the plane, |f2 - f1| = 2 exactly in float, s' = 2 (1 + 1e-6): the region L <= s' is
  // a needle-thin ellipse of area pi a b, so the mean weight is d/ds'(pi a b) = pi/2 (b + a^2/b).
  auto tris = square(3.0);
  Scene scene = makeScene(tris);
  dvec3 f1(-1.0, 0.0, 0.0), f2(1.0, 0.0, 0.0);
  SampleRun run = sample(scene, f1, f2, 2.0 * (1.0 + 1e-6), 1 << 16, 3);
  ASSERT_GT(run.hits, 0u);
  double a = 0.5 * run.s, b = std::sqrt((a - 1.0) * (a + 1.0));
  double expected = 0.5 * kPi * (b + a * a / b);
  EXPECT_NEAR(run.mean, expected, 4.5 * run.se + kFloatRel * expected) << "se " << run.se;
  // The same needle lifted above the plane misses it entirely.
  SampleRun above = sample(scene, f1 + dvec3(0, 0, 0.01), f2 + dvec3(0, 0, 0.01), 2.0 * (1.0 + 1e-6), 256, 4);
  EXPECT_EQ(above.hits, 0u);
}

TEST(HardEllipsoid, SphereTangentToPlane) {
  // f1 = f2 at height h: the cut is a circle and every sample's weight is d/ds'(pi (a^2 - h^2)) =
  // pi a, exactly, from tangency (r -> 0, |P_T grad L| -> 0) outwards.
  auto tris = square(2.0);
  Scene scene = makeScene(tris);
  dvec3 f(0.5, -0.3, 0.7);
  double h = float(0.7);
  SampleRun tangent = sample(scene, f, f, 2.0 * h, 256, 5);  // exactly tangent: a point, or nothing
  for (const SampleOut& o : tangent.out)
    if (o.ok) EXPECT_NEAR(o.weight, kPi * 0.5 * tangent.s, 1e-3 * kPi * tangent.s);
  for (double rel : {1e-6, 1e-4, 1e-2, 0.5}) {
    SampleRun run = sample(scene, f, f, 2.0 * h * (1.0 + rel), 4096, 6);
    ASSERT_EQ(run.hits, run.out.size()) << "rel " << rel;
    double expected = kPi * 0.5 * run.s;
    for (const SampleOut& o : run.out) ASSERT_NEAR(o.weight, expected, kFloatRel * expected) << "rel " << rel;
  }
}

TEST(HardEllipsoid, EllipsoidTangentToPlane) {
  // Tangent when s' = |f1 - mirror(f2)|; the region grows linearly in s' - s_t from there.
  auto tris = square(2.0);
  Scene scene = makeScene(tris);
  dvec3 f1(-0.4, 0.1, 0.5), f2(0.5, 0.3, 0.8);
  double st = glm::length(asFloat(f1) - asFloat(f2) * dvec3(1, 1, -1));
  SampleRun exact = sample(scene, f1, f2, st, 256, 7);
  (void)exact;  // finiteness is checked inside sample()
  for (double rel : {1e-4, 1e-2}) {
    SampleRun run = sample(scene, f1, f2, st * (1.0 + rel), 1 << 16, 8);
    ASSERT_GT(run.hits, 0u);
    expectMatchesQuadrature(tris, f1, f2, run, 0.25 * (run.s - st));
  }
}

TEST(HardEllipsoid, FocusOnTheSurface) {
  auto tris = square(2.0);
  Scene scene = makeScene(tris);
  dvec3 f1(0.2, -0.1, 0.0), f2(-0.3, 0.4, 0.6);
  double dist = glm::length(f2 - f1);
  for (double k : {1.05, 1.6}) {
    SampleRun run = sample(scene, f1, f2, k * dist, 1 << 16, 9);
    ASSERT_GT(run.hits, 0u);
    expectMatchesQuadrature(tris, f1, f2, run, 1e-4 * run.s);
  }
}

TEST(HardEllipsoid, HugeAndTinyScales) {
  for (double scale : {1e-3, 1.0, 1e3}) {
    std::vector<RefTriangle> tris = square(2.0 * scale);
    tris.push_back({dvec3(-0.5, -0.5, 0.3) * scale, dvec3(0.8, -0.2, 0.6) * scale, dvec3(0.0, 0.7, 1.0) * scale});
    Scene scene = makeScene(tris);
    dvec3 f1 = dvec3(-0.3, 0.2, 1.5) * scale, f2 = dvec3(0.4, -0.1, 1.2) * scale;
    SampleRun run = sample(scene, f1, f2, 3.0 * scale, 1 << 16, 10);
    ASSERT_GT(run.hits, 0u) << "scale " << scale;
    // d/ds' of an area is a length: it scales with the scene.
    expectMatchesQuadrature(tris, f1, f2, run, 1e-4 * run.s);
  }
}

}  // namespace
}  // namespace vktg::test
