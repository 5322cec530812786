// GPU vs CPU twin: the per-triangle conic of shaders/lib/ellipsoid.glsl (arcs, point, speed,
// barycentrics, selection weight, co-area ratio) against tests/support/ellipsoid_reference on
// thousands of random configurations.
//
// Tolerances come from float precision: the twin is evaluated at the exact float inputs and at
// copies perturbed by a few float ulps; the spread of those evaluations measures how much float
// rounding can move each output (it grows near tangencies and vertices, where the problem is
// ill-conditioned). A configuration whose perturbed copies disagree on the arc structure is
// ill-conditioned: only finiteness is checked there, and such cases must stay rare.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "support/ellipsoid_reference.h"
#include "support/gpu_test.h"

namespace vktg::test {
namespace {

struct ConicIn {
  float f1[3], f2[3], s, p0[3], p1[3], p2[3], u, pad[3];
};
struct ConicOut {
  uint32_t ok, count;
  float total, weight, arcStart[3], arcLength[3], phi, position[3], bary[2], speed, ratio, ratioScale, pad;
};
static_assert(sizeof(ConicIn) == 80 && sizeof(ConicOut) == 80);

dvec3 toD(const float* v) { return dvec3(v[0], v[1], v[2]); }

// Outputs of the twin compared with the GPU, in one flat list (angles separately: they wrap).
struct TwinOut {
  bool ok = false;
  int count = 0;
  std::vector<double> values;  // total, weight, arc lengths, position, bary, speed, ratio, ratioScale
  std::vector<double> angles;  // arc starts, phi
};

TwinOut twin(const ConicIn& in) {
  TwinOut o;
  EllipseArcsRef arcs;
  RefTriangle tri{toD(in.p0), toD(in.p1), toD(in.p2)};
  o.ok = ellipseOnTriangleRef(toD(in.f1), toD(in.f2), in.s, tri, arcs);
  o.count = arcs.count;
  if (!o.ok) return o;
  double phi = ellipseArcPhiRef(arcs, in.u);
  dvec3 x = ellipsePointRef(arcs, phi);
  dvec2 bc = ellipseBarycentricsRef(arcs, phi);
  o.values = {arcs.total, arcs.weight, arcs.arcLength[0], arcs.arcLength[1], arcs.arcLength[2], x.x, x.y, x.z,
              bc.x, bc.y, ellipseSpeedRef(arcs, phi), ellipseCoareaRatioRef(arcs, toD(in.f1), toD(in.f2), x),
              arcs.ratioScale};
  o.angles = {arcs.arcStart[0], arcs.arcStart[1], arcs.arcStart[2], phi};
  return o;
}

std::vector<double> gpuValues(const ConicOut& g) {
  return {g.total, g.weight, g.arcLength[0], g.arcLength[1], g.arcLength[2], g.position[0], g.position[1],
          g.position[2], g.bary[0], g.bary[1], g.speed, g.ratio, g.ratioScale};
}

double angleDiff(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * std::numbers::pi)); }

TEST(GpuEllipsoid, ConicMatchesCpuTwin) {
  const int n = 4096;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f), unit(0.0f, 1.0f);
  std::vector<ConicIn> inputs(n);
  for (int i = 0; i < n; ++i) {
    ConicIn& in = inputs[i];
    for (int k = 0; k < 3; ++k) {
      in.f1[k] = coord(rng);
      in.f2[k] = (i % 8 == 0) ? in.f1[k] : coord(rng);  // every 8th: f1 == f2, a sphere
      in.p0[k] = coord(rng);
      in.p1[k] = coord(rng);
      in.p2[k] = coord(rng);
      in.pad[k] = 0.0f;
    }
    float dist = float(glm::length(toD(in.f2) - toD(in.f1)));
    // Mostly solvable lengths; every 16th at or below the focal distance (no solution).
    in.s = (i % 16 == 1) ? dist * unit(rng) : dist + 3.0f * unit(rng);
    in.u = unit(rng);
  }
  auto out = runKernel<ConicOut>("ellipsoid_conic", inputs, n, n);

  const double ulp = std::ldexp(1.0, -23);
  std::mt19937_64 prng(11);
  std::uniform_real_distribution<double> sym(-1.0, 1.0);
  int compared = 0, illConditioned = 0, solvable = 0;
  for (int i = 0; i < n; ++i) {
    const ConicIn& in = inputs[i];
    const ConicOut& g = out[i];
    for (double v : gpuValues(g)) ASSERT_TRUE(std::isfinite(v)) << "case " << i;
    TwinOut ref = twin(in);
    if (in.s <= float(glm::length(toD(in.f2) - toD(in.f1)))) {
      ASSERT_EQ(g.ok, 0u) << "case " << i << ": no solution expected";
      ASSERT_FALSE(ref.ok);
      continue;
    }
    // Spread of the twin under input perturbations of 8 ulps (of the unit coordinate scale).
    std::vector<double> spread(ref.values.size(), 0.0), angleSpread(ref.angles.size(), 0.0);
    bool stable = true;
    for (int p = 0; p < 6 && stable; ++p) {
      ConicIn q = in;
      float* fields[] = {q.f1, q.f2, q.p0, q.p1, q.p2};
      for (float* f : fields)
        for (int k = 0; k < 3; ++k) f[k] = float(f[k] + 8.0 * ulp * sym(prng));
      q.s = float(q.s * (1.0 + 8.0 * ulp * sym(prng)));
      TwinOut t = twin(q);
      if (t.ok != ref.ok || t.count != ref.count) {
        stable = false;
        break;
      }
      for (size_t k = 0; k < spread.size(); ++k) spread[k] = std::max(spread[k], std::abs(t.values[k] - ref.values[k]));
      for (size_t k = 0; k < angleSpread.size(); ++k)
        angleSpread[k] = std::max(angleSpread[k], angleDiff(t.angles[k], ref.angles[k]));
    }
    if (!stable) {
      ++illConditioned;
      continue;
    }
    ++compared;
    ASSERT_EQ(g.ok != 0u, ref.ok) << "case " << i;
    if (!ref.ok) continue;
    ++solvable;
    ASSERT_EQ(int(g.count), ref.count) << "case " << i;
    std::vector<double> gv = gpuValues(g);
    // 4x the perturbation spread (the GPU also rounds every intermediate), plus 64 ulps of the
    // value's own magnitude for outputs that the perturbation happens not to move.
    for (size_t k = 0; k < gv.size(); ++k) {
      double tol = 4.0 * spread[k] + 64.0 * ulp * std::max(std::abs(ref.values[k]), 1.0);
      ASSERT_NEAR(gv[k], ref.values[k], tol) << "case " << i << " output " << k;
    }
    double ga[4] = {g.arcStart[0], g.arcStart[1], g.arcStart[2], g.phi};
    for (int k = 0; k < 4; ++k) {
      if (k < 3 && k >= ref.count) continue;
      ASSERT_LE(angleDiff(ga[k], ref.angles[k]), 4.0 * angleSpread[k] + 64.0 * ulp) << "case " << i << " angle " << k;
    }
  }
  // Ill-conditioned cases are those within a few ulps of a tangency or a vertex: rare.
  EXPECT_LT(illConditioned, n / 50) << illConditioned << " ill-conditioned of " << n;
  EXPECT_GT(solvable, n / 8) << "too few configurations where the ellipse meets the triangle";
  EXPECT_GT(compared, n / 2);
  std::printf("compared %d (ellipse meets triangle: %d), ill-conditioned %d of %d\n", compared, solvable,
              illConditioned, n);
}

// The closed-form co-area ratio equals |x'| / |P_T grad L| from the definition, on the twin
// itself (double precision, generic configurations, away from tangency).
TEST(GpuEllipsoid, TwinCoareaClosedFormMatchesDefinition) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), unit(0.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    dvec3 f1(coord(rng), coord(rng), coord(rng));
    dvec3 f2 = (i % 4 == 0) ? f1 : dvec3(coord(rng), coord(rng), coord(rng));
    RefTriangle tri{{coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)},
                    {coord(rng), coord(rng), coord(rng)}};
    double s = glm::length(f2 - f1) + 3.0 * unit(rng);
    EllipseArcsRef arcs;
    if (!ellipseOnTriangleRef(f1, f2, s, tri, arcs)) continue;
    double phi = ellipseArcPhiRef(arcs, unit(rng));
    dvec3 x = ellipsePointRef(arcs, phi);
    dvec3 normal = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    double grad = projectedGradientRef(f1, f2, x, normal);
    if (grad < 1e-3) continue;  // near tangency the definition itself loses digits
    ++checked;
    EXPECT_NEAR(pathLengthRef(f1, f2, x), s, 1e-12 * s);
    dvec2 bc = ellipseBarycentricsRef(arcs, phi);
    dvec3 xb = tri.p0 + bc.x * (tri.p1 - tri.p0) + bc.y * (tri.p2 - tri.p0);
    EXPECT_LT(glm::length(xb - x), 1e-10);
    EXPECT_NEAR(ellipseSpeedRef(arcs, phi) / grad, ellipseCoareaRatioRef(arcs, f1, f2, x),
                1e-9 * ellipseCoareaRatioRef(arcs, f1, f2, x));
  }
  EXPECT_GT(checked, 200);
}

}  // namespace
}  // namespace vktg::test
