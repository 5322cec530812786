// Statistical tests of sampleEllipsoidConnection (shaders/lib/ellipsoid.glsl), choosing triangles
// by enumeration (kEllipsoidEnumerate; the descent: stat_ellipsoid_descent.cpp), on a small scene:
// a square plane of two triangles and a tilted triangle above it, foci above both.
//  1. Area density: draw s' from a smooth known density p_s, sample a connection, histogram the
//     points per triangle. Their area density is p_s(L(x)) * |P_T grad L| * pdf_l(x) =
//     p_s(L(x)) * density(x) (density = 1 / weight, CPU twin); a wrong Jacobian anywhere in the
//     chain (co-area factor, curve pdf, selection) shows up as a chi-square failure.
//  2. Unbiasedness, independent of the twin: for fixed s', mean(weight) must equal d/ds' of the
//     area of {x on the surfaces : L(x) <= s'}, computed by quadrature of the surfaces.
//  3. ellipsoidConnectionDensity (GPU) equals 1 / weight of the sample it describes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "support/chi2.h"
#include "support/ellipsoid_kernel.h"
#include "support/ellipsoid_reference.h"
#include "support/gpu_test.h"

namespace vktg::test {
namespace {

Scene makeScene(const std::vector<RefTriangle>& tris) {
  return sceneOfShapes({shapeOfTriangles("plane", {tris[0], tris[1]}), shapeOfTriangles("tilted", {tris[2]})});
}

// Index in `tris` of the GPU triangle with these vertices (any vertex order), or -1.
int matchTriangle(const std::vector<RefTriangle>& tris, const EllipsoidSampleOut& o) {
  dvec3 g[3] = {dvec3(o.p0[0], o.p0[1], o.p0[2]), dvec3(o.p1[0], o.p1[1], o.p1[2]), dvec3(o.p2[0], o.p2[1], o.p2[2])};
  for (size_t t = 0; t < tris.size(); ++t) {
    dvec3 v[3] = {tris[t].p0, tris[t].p1, tris[t].p2};
    bool all = true;
    for (const dvec3& q : g) all = all && std::any_of(v, v + 3, [&](const dvec3& w) { return glm::length(q - w) < 1e-6; });
    if (all) return int(t);
  }
  return -1;
}

// (a, b) in [0, 1]^2 with u = a (1 - b), v = b: a square chart of the triangle without the
// density jump along u + v = 1; dA = 2 area (1 - b) da db.
dvec2 squareChart(const RefTriangle& tri, dvec3 x) {
  dvec3 e01 = tri.p1 - tri.p0, e02 = tri.p2 - tri.p0, q = x - tri.p0;
  double d00 = glm::dot(e01, e01), d01 = glm::dot(e01, e02), d11 = glm::dot(e02, e02);
  double q0 = glm::dot(q, e01), q1 = glm::dot(q, e02);
  double det = d00 * d11 - d01 * d01;
  double u = (d11 * q0 - d01 * q1) / det, v = (d00 * q1 - d01 * q0) / det;
  double b = std::clamp(v, 0.0, 1.0);
  double a = b < 1.0 ? std::clamp(u / (1.0 - b), 0.0, 1.0) : 0.0;
  return {a, b};
}

// s' ~ lo + (hi - lo) Beta(3, 3): smooth (C1) at both ends, so the area density has no jumps.
const double kSLo = 2.0, kSHi = 3.6;
double betaDensity(double s) {
  if (s <= kSLo || s >= kSHi) return 0.0;
  double t = (s - kSLo) / (kSHi - kSLo);
  return 30.0 * t * t * (1 - t) * (1 - t) / (kSHi - kSLo);
}

// Inputs at length fixedS, or (fixedS <= 0) at lengths drawn from betaDensity.
std::vector<EllipsoidSampleIn> makeInputs(size_t n, uint32_t seed, double fixedS) {
  return planeAndTiltedInputs(n, seed, [fixedS](std::mt19937& rng) {
    if (fixedS > 0.0) return float(fixedS);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    float m[5];
    for (float& v : m) v = unit(rng);
    std::nth_element(m, m + 2, m + 5);  // median of 5 uniforms ~ Beta(3, 3)
    return float(kSLo + (kSHi - kSLo) * m[2]);
  });
}

TEST(StatEllipsoid, AreaDensityChiSquare) {
  std::vector<RefTriangle> tris = planeAndTiltedTriangles();
  Scene scene = makeScene(tris);
  const size_t n = 200000;
  auto in = makeInputs(n, 21, 0.0);
  auto out = runKernel<EllipsoidSampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene, gpu::kEllipsoidEnumerate);

  // Chart: x in [t, t + 1) is triangle t's a-coordinate, y its b-coordinate.
  std::vector<dvec2> samples;
  size_t densityMismatch = 0;
  for (size_t i = 0; i < n; ++i) {
    const EllipsoidSampleOut& o = out[i];
    if (!o.ok) continue;
    ASSERT_TRUE(std::isfinite(o.weight) && o.weight > 0.0f) << i;
    int t = matchTriangle(tris, o);
    ASSERT_GE(t, 0) << "sample " << i << " on an unknown triangle";
    dvec3 x(o.position[0], o.position[1], o.position[2]);
    // The sample lies on its triangle and on the ellipsoid (float precision of unit-scale data).
    ASSERT_NEAR(pathLengthRef(kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, x), in[i].s, 1e-5) << i;
    dvec3 g0(o.p0[0], o.p0[1], o.p0[2]), g1(o.p1[0], o.p1[1], o.p1[2]), g2(o.p2[0], o.p2[1], o.p2[2]);
    ASSERT_LT(glm::length(g0 + double(o.bary[0]) * (g1 - g0) + double(o.bary[1]) * (g2 - g0) - x), 1e-5) << i;
    if (!(std::abs(double(o.density) * o.weight - 1.0) < 1e-4)) ++densityMismatch;
    dvec2 ab = squareChart(tris[t], x);
    samples.push_back({std::min(t + ab.x, t + 1.0 - 1e-12), ab.y});
  }
  EXPECT_EQ(densityMismatch, 0u) << "ellipsoidConnectionDensity != 1 / weight";

  auto density = [&](double cx, double b) {
    int t = std::clamp(int(std::floor(cx)), 0, int(tris.size()) - 1);
    double a = cx - t;
    const RefTriangle& tri = tris[t];
    dvec3 x = tri.p0 + a * (1.0 - b) * (tri.p1 - tri.p0) + b * (tri.p2 - tri.p0);
    double s = pathLengthRef(kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, x);
    double pA = betaDensity(s) * ellipsoidDensityRef(tris, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, size_t(t), x);
    return pA * glm::length(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0)) * (1.0 - b);
  };
  Grid2D grid{0.0, double(tris.size()), 0.0, 1.0, 12 * int(tris.size()), 12};
  Chi2Result r = chi2Test2D(grid, samples, n, density, Chi2Options{});
  EXPECT_TRUE(r.passed) << r.report;
  // The density must integrate to the probability that the shell meets a surface at all:
  // the p_s-mass of the lengths s' for which some triangle has a clipped arc (midpoint rule; the
  // indicator's one jump costs at most one step times max p_s = 1.9e-5, Simpson's cell tolerance
  // adds ~1e-6).
  const int steps = 100000;
  double hitMass = 0.0;
  for (int i = 0; i < steps; ++i) {
    double s = kSLo + (i + 0.5) / steps * (kSHi - kSLo);
    bool met = false;
    for (const RefTriangle& tri : tris) {
      EllipseArcsRef arcs;
      met = met || ellipseOnTriangleRef(kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, tri, arcs);
    }
    if (met) hitMass += betaDensity(s) * (kSHi - kSLo) / steps;
  }
  EXPECT_NEAR(r.densityMass, hitMass, 1e-4) << "the density's total mass is not the probability of a sample";
  EXPECT_LT(hitMass, 0.99) << "the s' range should include lengths that meet nothing";
}

// d/ds' Area{L <= s'} by quadrature, with an error estimate from halving the step and doubling rows.
struct Reference {
  double value, error;
};
Reference areaDerivative(const std::vector<RefTriangle>& tris, double s) {
  double coarse = shellAreaDerivative(tris, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, 1e-4 * s, 3000);
  double fine = shellAreaDerivative(tris, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, 5e-5 * s, 6000);
  return {fine, std::abs(fine - coarse)};
}

TEST(StatEllipsoid, MeanWeightIsAreaDerivative) {
  std::vector<RefTriangle> tris = planeAndTiltedTriangles();
  Scene scene = makeScene(tris);
  // 2.2: tilted triangle only; 2.9 and 3.1: the plane (both triangles) as well.
  for (double s : {2.2, 2.9, 3.1}) {
    const size_t n = 1 << 17;
    auto in = makeInputs(n, 5 + uint32_t(s * 10), s);
    auto out = runKernel<EllipsoidSampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene, gpu::kEllipsoidEnumerate);
    double sum = 0.0, sq = 0.0;
    for (const EllipsoidSampleOut& o : out) {
      ASSERT_TRUE(std::isfinite(o.weight));
      double w = o.ok ? o.weight : 0.0;
      sum += w;
      sq += w * w;
    }
    double mean = sum / n;
    double se = std::sqrt(std::max(sq / n - mean * mean, 0.0) / (n - 1));
    Reference ref = areaDerivative(tris, double(in[0].s));
    ASSERT_GT(ref.value, 0.0);
    // 4.5 standard errors of the estimate, the quadrature's own error, and float32 evaluation of
    // the weight (a few hundred ulps at most).
    double tol = 4.5 * se + 2.0 * ref.error + 256.0 * std::ldexp(1.0, -24) * ref.value;
    EXPECT_NEAR(mean, ref.value, tol) << "s' = " << s << " se = " << se << " quadrature error = " << ref.error;
  }
}

}  // namespace
}  // namespace vktg::test
