// Forward-mode derivative building blocks (shaders/lib/dual.glsl, geometry_dual.glsl, bsdf_dual.glsl)
// on thousands of random configurations each, through tests/shaders/dual_*.comp:
//  - every dual derivative equals the central finite difference of the double-precision CPU twin
//    (tests/support/dual_reference.h; bsdf_reference.h for the BSDF; Gate::weight for gates);
//  - every dual value equals the non-dual float function within twice the float bound of either:
//    both run the same operations on the same inputs, but a GPU compiler may fuse a*b+c or reorder
//    differently in the two, so bit equality is not theirs to promise (valueFloatScale);
//  - the ray-form hit's derivative also equals its closed form in double, and the finite difference
//    of re-intersecting the moved triangle in double.
//
// Tolerance of one comparison (derivations in tests/support/dual_reference.h):
//   |gpu - fd| <= truncation + N u (terms + conditioning)
// truncation: |D(h/4) - D(h/2)| plus double rounding, an over-estimate (3x) of the error left in the
// Richardson value; u = 2^-24 the float unit roundoff; N the number of float operations a
// derivative passes through (forward error of an N-operation chain is <= N u relative to its
// terms; rounded intermediates act like relative input perturbations, which `conditioning` scales):
// kOpsUlps for single operations (at most ~6 operations each), kGeometryUlps for the geometry (cross
// product, normalisation, dot products and divisions: under 40), kBsdfUlps for the BSDF: some 200
// operations from the frame to the final division, about 30 of them divisions, square roots and
// normalisations, each counted at the error Vulkan allows it (tests/support/bsdf_reference.h: up
// to 9 u for a square root, 5 u for a division): 170 + 30 x 9 = 440 u, so 512. The step h = 2^-13 (tangents are O(1)) keeps
// truncation near 1e-8 relative for smooth pieces while the double differences stay at 1e-11.
// A Dual3 result takes the largest float scale of its three components (see vectorScale). Each
// tally prints the worst measured error in units of u (terms + conditioning), so a drift toward
// the bound shows (at the time of writing, lavapipe: operations 11, geometry 15, BSDF 233 of 512;
// an NVIDIA H200, whose divisions and square roots are not correctly rounded: BSDF 340).
//
// Excluded, counted and printed: (1) configurations whose stencil meets a kink or jump (the
// step-halving test of centralDifference: a branch, a clamp, a cut-off, the two-sided flip, total
// internal reflection, a gate edge), where no finite difference measures a derivative; (2) those
// whose tolerance exceeds a tenth of the derivative's scale (max(|fd|, terms)): there the comparison
// would prove nothing (a float derivative near grazing angles or the critical angle, sharp lobes),
// and BSDF configurations where the float primal itself is ill-conditioned by tests/gpu_bsdf.cpp's
// criterion (bsdfFloatTolerance(kappa) > 1e-2: near the critical angle the float bsdfEval can be 0
// where the double twin is not, so no derivative of it can match).
// Each test asserts that exclusions stay below a fraction of its configurations, so a broken twin
// or kernel cannot pass by being excluded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "support/bsdf_reference.h"
#include "support/dual_reference.h"
#include "support/gpu_test.h"
#include "support/test_gates.h"
#include "vktg/gate.h"

namespace vktg::test {
namespace {

constexpr double kUnitRoundoff = 5.9604644775390625e-8;  // 2^-24
constexpr double kStep = 1.0 / 8192.0;                   // 2^-13
constexpr double kOpsUlps = 16.0;
constexpr double kGeometryUlps = 64.0;
constexpr double kBsdfUlps = 512.0;
constexpr double kMaxRelativeTolerance = 0.1;
constexpr int kMaxReported = 12;

// Tally of one family of comparisons.
struct Tally {
  std::string name;
  size_t compared = 0, nonSmooth = 0, illConditioned = 0, failed = 0, valueMismatches = 0;
  double worstUlps = 0.0;  // worst |gpu - fd| beyond truncation, in units of u (terms + conditioning)

  void print() const {
    std::printf("[ grad ] %-28s compared %zu, excluded %zu (kink/jump in stencil) + %zu (ill-conditioned), "
                "failed %zu, worst float error %.1f u x scale, value mismatches %zu\n",
                name.c_str(), compared, nonSmooth, illConditioned, failed, worstUlps, valueMismatches);
  }
  size_t total() const { return compared + nonSmooth + illConditioned; }
};

struct Input {
  std::vector<double> x, tangent;
  std::vector<int> groups;
  std::vector<bool> frozen;
};

// Compares a GPU derivative with the finite difference of `f` along the input's tangent.
// `shared` (vector outputs) replaces the component's own float scale by that of the whole vector.
void compareDerivative(Tally& t, float gpu, const ScalarFunction& f, const Input& in, double ulps, uint64_t seed,
                       const std::string& what, const FloatScale* shared = nullptr) {
  FiniteDifference fd = centralDifference(f, in.x, in.tangent, kStep);
  if (!fd.smooth) {
    ++t.nonSmooth;
    return;
  }
  FloatScale s = shared ? *shared : floatScale(f, in.x, in.tangent, in.groups, in.frozen, kStep, seed);
  double floatPart = ulps * kUnitRoundoff * (s.terms + s.conditioning);
  double tol = fd.truncation + floatPart;
  double scale = std::max(std::abs(fd.derivative), s.terms);
  // A derivative whose every term vanishes (a flat gate, a clamped roughness) must come out as 0:
  // compared against the truncation bound alone, never excluded.
  if (scale > 0.0 && tol > kMaxRelativeTolerance * scale) {
    ++t.illConditioned;
    return;
  }
  ++t.compared;
  double err = std::abs(double(gpu) - fd.derivative);
  if (s.terms + s.conditioning > 0.0)
    t.worstUlps = std::max(t.worstUlps, std::max(0.0, err - fd.truncation) / (kUnitRoundoff * (s.terms + s.conditioning)));
  if (!std::isfinite(gpu) || !(err <= tol)) {
    if (++t.failed <= kMaxReported)
      ADD_FAILURE() << t.name << " " << what << ": gpu " << gpu << " fd " << fd.derivative << " tolerance " << tol
                    << " (truncation " << fd.truncation << ", terms " << s.terms << ", conditioning "
                    << s.conditioning << ")";
  }
}

// The float scale of a Dual3 result: the largest of its components'. Its components share their
// intermediates (a normalisation's radial part, say), whose rounding errs relative to the whole
// vector, so a component that cancels to near 0 still carries the vector's error.
FloatScale vectorScale(const std::vector<ScalarFunction>& f, size_t first, const Input& in, uint64_t seed) {
  FloatScale v;
  for (size_t k = first; k < first + 3; ++k) {
    FloatScale s = floatScale(f[k], in.x, in.tangent, in.groups, in.frozen, kStep, seed + k);
    v.terms = std::max(v.terms, s.terms);
    v.conditioning = std::max(v.conditioning, s.conditioning);
  }
  return v;
}

// The dual's value part against the plain float function: each errs by at most N u times the
// value's float scale, so they differ by at most twice that.
void compareValue(Tally& t, float dualValue, float plain, const ScalarFunction& f, const Input& in, double ulps,
                  uint64_t seed, const std::string& what) {
  if (std::memcmp(&dualValue, &plain, sizeof(float)) == 0) return;
  double allowed = 2.0 * ulps * kUnitRoundoff * valueFloatScale(f, in.x, in.frozen, seed);
  if (std::abs(double(dualValue) - double(plain)) <= allowed) return;
  if (++t.valueMismatches <= kMaxReported)
    ADD_FAILURE() << t.name << " " << what << ": dual value " << dualValue << " vs plain " << plain << ", allowed "
                  << allowed;
}

void expectFewExclusions(const Tally& t, double fraction) {
  t.print();
  EXPECT_EQ(t.failed, 0u) << t.name;
  EXPECT_EQ(t.valueMismatches, 0u) << t.name;
  EXPECT_GT(t.compared, 0u) << t.name;
  EXPECT_LE(double(t.nonSmooth + t.illConditioned), fraction * double(t.total())) << t.name;
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

// Float-representable random vector (the kernel sees exactly these numbers).
glm::dvec3 randomVector(std::mt19937_64& rng, double lo, double hi) {
  return glm::dvec3(glm::vec3(float(uniform(rng, lo, hi)), float(uniform(rng, lo, hi)), float(uniform(rng, lo, hi))));
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    glm::dvec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3) return glm::dvec3(glm::vec3(glm::normalize(v)));
  }
}

glm::dvec3 at(const std::vector<double>& x, size_t i) { return {x[i], x[i + 1], x[i + 2]}; }

void push(std::vector<double>& x, const glm::dvec3& v) { x.insert(x.end(), {v.x, v.y, v.z}); }

// ---- Elementary operations ------------------------------------------------------------------------

// x = [a, b, c, p, A(3), B(3)]: the twin of each of dual_ops.comp's 39 output components.
std::vector<ScalarFunction> opsComponents() {
  std::vector<ScalarFunction> f;
  auto A = [](const std::vector<double>& x) { return at(x, 4); };
  auto B = [](const std::vector<double>& x) { return at(x, 7); };
  f.push_back([](const std::vector<double>& x) { return x[0] + x[1]; });
  f.push_back([](const std::vector<double>& x) { return x[0] - x[1]; });
  f.push_back([](const std::vector<double>& x) { return x[0] * x[1]; });
  f.push_back([](const std::vector<double>& x) { return x[0] / x[1]; });
  f.push_back([](const std::vector<double>& x) { return -x[0]; });
  f.push_back([](const std::vector<double>& x) { return std::sqrt(x[0]); });
  f.push_back([](const std::vector<double>& x) { return std::exp(x[1]); });
  f.push_back([](const std::vector<double>& x) { return std::log(x[0]); });
  f.push_back([](const std::vector<double>& x) { return std::pow(x[0], x[3]); });
  f.push_back([](const std::vector<double>& x) { return std::abs(x[1]); });
  f.push_back([](const std::vector<double>& x) { return std::max(x[1], x[2]); });
  f.push_back([](const std::vector<double>& x) { return std::clamp(x[1], x[2] - 0.5, x[2] + 0.5); });
  f.push_back([](const std::vector<double>& x) { return x[0] * x[2]; });
  f.push_back([](const std::vector<double>& x) { return x[0] / x[2]; });
  f.push_back([](const std::vector<double>& x) { return x[2] / x[0]; });
  f.push_back([](const std::vector<double>& x) { return x[2] - x[0]; });
  f.push_back([](const std::vector<double>& x) { return x[0] + x[2]; });
  f.push_back([=](const std::vector<double>& x) { return glm::dot(A(x), B(x)); });
  f.push_back([=](const std::vector<double>& x) { return glm::length(A(x)); });
  f.push_back([=](const std::vector<double>& x) { return glm::distance(A(x), B(x)); });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return glm::cross(A(x), B(x))[k]; });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return glm::normalize(A(x))[k]; });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return A(x)[k] * x[0]; });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return A(x)[k] * x[2]; });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return A(x)[k] + B(x)[k]; });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return A(x)[k] - B(x)[k]; });
  f.push_back([](const std::vector<double>& x) { return std::min(x[1], x[2]); });
  return f;
}

TEST(GradFunctions, DualOperationsMatchFiniteDifferences) {
  constexpr uint32_t kCount = 4096;
  const std::vector<ScalarFunction> components = opsComponents();
  ASSERT_EQ(components.size(), 39u);
  std::mt19937_64 rng(11);
  std::vector<float> words;
  std::vector<Input> inputs;
  for (uint32_t i = 0; i < kCount; ++i) {
    float a = float(uniform(rng, 0.2, 3.0)), ad = float(uniform(rng, -2, 2));
    float c = float(uniform(rng, 0.2, 1.5) * (rng() & 1 ? 1 : -1));
    float b = float(uniform(rng, -2, 2)), bd = float(uniform(rng, -2, 2));
    // Every 16th configuration sits on a kink of abs, max, min or clamp (excluded, counted).
    if (i % 16 == 0) b = (i / 16) % 3 == 0 ? 0.0f : (i / 16) % 3 == 1 ? c : c + 0.5f;
    float p = float(uniform(rng, -2.5, 2.5));
    glm::dvec3 A = randomVector(rng, -1.5, 1.5), Ad = randomVector(rng, -1, 1);
    glm::dvec3 B = randomVector(rng, -1.5, 1.5), Bd = randomVector(rng, -1, 1);
    if (glm::length(A) < 0.3 || glm::distance(A, B) < 0.3) {
      --i;
      continue;
    }
    words.insert(words.end(), {a, ad, b, bd, c, p, 0, 0, float(A.x), float(A.y), float(A.z), 0, float(Ad.x),
                               float(Ad.y), float(Ad.z), 0, float(B.x), float(B.y), float(B.z), 0, float(Bd.x),
                               float(Bd.y), float(Bd.z), 0});
    Input in;
    in.x = {a, b, c, p};
    push(in.x, A);
    push(in.x, B);
    in.tangent = {ad, bd, 0, 0};
    push(in.tangent, Ad);
    push(in.tangent, Bd);
    in.groups = {0, 1, 2, 2, 3, 3, 3, 4, 4, 4};
    in.frozen.assign(in.x.size(), false);
    inputs.push_back(in);
  }
  const size_t stride = 3 * components.size();
  std::vector<float> out = runKernel<float>("dual_ops", words, stride * kCount, kCount);
  Tally t{"dual operations"};
  for (uint32_t i = 0; i < kCount; ++i) {
    FloatScale vec;
    for (size_t k = 0; k < components.size(); ++k) {
      const float* o = &out[i * stride + 3 * k];
      std::string what = "config " + std::to_string(i) + " component " + std::to_string(k);
      compareValue(t, o[0], o[2], components[k], inputs[i], kOpsUlps, i * 64 + k, what);
      const bool vector = k >= 20 && k < 38;  // cross, normalize, scale (2), add, sub
      if (vector && (k - 20) % 3 == 0) vec = vectorScale(components, k, inputs[i], i * 64);
      compareDerivative(t, o[1], components[k], inputs[i], kOpsUlps, i * 64 + k, what, vector ? &vec : nullptr);
    }
  }
  // The deliberate kinks are 1/16 of the configurations, on 4 of 39 components.
  expectFewExclusions(t, 0.01);
}

// ---- Geometry -------------------------------------------------------------------------------------

// x = [p0, p1, p2, q, o, w (3 each), u, v].
struct GeometryTwin {
  static glm::dvec3 p(const std::vector<double>& x, int i) { return at(x, 3 * i); }
  static glm::dvec3 q(const std::vector<double>& x) { return at(x, 9); }
  static glm::dvec3 o(const std::vector<double>& x) { return at(x, 12); }
  static glm::dvec3 w(const std::vector<double>& x) { return at(x, 15); }
  // The ray's hit on the moved triangle's plane, by re-intersecting (the twin of rayHitDual).
  static glm::dvec3 hit(const std::vector<double>& x) {
    auto h = intersectPlaneReference(o(x), w(x), p(x, 0), p(x, 1), p(x, 2));
    return h ? o(x) + h->t * w(x) : glm::dvec3(std::nan(""));
  }
};

std::vector<ScalarFunction> geometryComponents(double baseArea) {
  using G = GeometryTwin;
  std::vector<ScalarFunction> f;
  f.push_back([](const std::vector<double>& x) { return segmentLengthReference(G::p(x, 0), G::q(x)); });
  for (int k = 0; k < 3; ++k)
    f.push_back([=](const std::vector<double>& x) { return segmentDirectionReference(G::p(x, 0), G::q(x))[k]; });
  for (int k = 0; k < 3; ++k)
    f.push_back([=](const std::vector<double>& x) { return triangleNormalReference(G::p(x, 0), G::p(x, 1), G::p(x, 2))[k]; });
  f.push_back([](const std::vector<double>& x) { return triangleAreaReference(G::p(x, 0), G::p(x, 1), G::p(x, 2)); });
  f.push_back([=](const std::vector<double>& x) {
    return triangleAreaReference(G::p(x, 0), G::p(x, 1), G::p(x, 2)) / baseArea;
  });
  f.push_back([](const std::vector<double>& x) {
    return std::abs(glm::dot(triangleNormalReference(G::p(x, 0), G::p(x, 1), G::p(x, 2)),
                             segmentDirectionReference(G::p(x, 0), G::q(x))));
  });
  for (int k = 0; k < 3; ++k) f.push_back([=](const std::vector<double>& x) { return G::hit(x)[k]; });
  f.push_back([](const std::vector<double>& x) { return glm::distance(G::hit(x), G::o(x)); });
  return f;
}

TEST(GradFunctions, GeometryMatchesFiniteDifferencesAndReintersection) {
  constexpr uint32_t kCount = 4096;
  std::mt19937_64 rng(12);
  std::vector<float> words;
  std::vector<Input> inputs;
  std::vector<double> areas;
  std::vector<glm::dvec3> closedForm, exactClosedForm;
  size_t grazingCos = 0;
  while (inputs.size() < kCount) {
    glm::dvec3 p[3], v[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = randomVector(rng, -1, 1);
      v[k] = randomVector(rng, -1, 1);
    }
    double maxEdge = std::max({glm::distance(p[0], p[1]), glm::distance(p[1], p[2]), glm::distance(p[2], p[0])});
    if (triangleAreaReference(p[0], p[1], p[2]) < 0.05 * maxEdge * maxEdge) continue;  // no slivers
    glm::dvec3 q = randomVector(rng, -2, 2), qd = randomVector(rng, -1, 1);
    if (glm::distance(q, p[0]) < 0.3) continue;
    double u = uniform(rng, 0.1, 0.8), vv = uniform(rng, 0.1, 0.8);
    if (u + vv > 0.9) continue;
    float uf = float(u), vf = float(vv);
    glm::dvec3 x = (1.0 - uf - vf) * p[0] + double(uf) * p[1] + double(vf) * p[2];
    glm::dvec3 w = randomUnit(rng);
    glm::dvec3 n = triangleNormalReference(p[0], p[1], p[2]);
    if (std::abs(glm::dot(n, w)) < 0.1) continue;  // grazing: the hit's velocity 1 / cos blows up
    glm::dvec3 o = glm::dvec3(glm::vec3(x - uniform(rng, 0.5, 3.0) * w));
    Input in;
    for (int k = 0; k < 3; ++k) push(in.x, p[k]);
    push(in.x, q);
    push(in.x, o);
    push(in.x, w);
    in.x.insert(in.x.end(), {double(uf), double(vf)});
    for (int k = 0; k < 3; ++k) push(in.tangent, v[k]);
    push(in.tangent, qd);
    in.tangent.resize(in.x.size(), 0.0);
    in.groups = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4};
    in.frozen.assign(in.x.size(), false);
    for (size_t k = 0; k < 18; ++k) words.push_back(float(k < 9 ? in.x[k] : in.tangent[k - 9]));
    words.insert(words.end(), {float(q.x), float(q.y), float(q.z), float(qd.x), float(qd.y), float(qd.z),
                               float(o.x), float(o.y), float(o.z), float(w.x), float(w.y), float(w.z), uf, vf});
    if (std::abs(glm::dot(n, segmentDirectionReference(p[0], q))) < 1e-3) ++grazingCos;
    inputs.push_back(in);
    areas.push_back(triangleAreaReference(p[0], p[1], p[2]));
    closedForm.push_back(rayHitVelocityReference(w, p[0], p[1], p[2], v[0], v[1], v[2], uf, vf));
    // The float ray meets the triangle within ~1e-7 of (uf, vf); re-intersection differentiates at
    // that exact hit, so its closed form is evaluated there.
    auto exact = intersectPlaneReference(o, w, p[0], p[1], p[2]);
    exactClosedForm.push_back(rayHitVelocityReference(w, p[0], p[1], p[2], v[0], v[1], v[2], exact->u, exact->v));
  }
  constexpr size_t kComponents = 14;
  std::vector<float> out = runKernel<float>("dual_geometry", words, 3 * kComponents * kCount, kCount);
  Tally t{"geometry"}, hitClosed{"ray hit vs closed form"}, closedFd{"closed form vs re-intersection"};
  for (uint32_t i = 0; i < kCount; ++i) {
    std::vector<ScalarFunction> f = geometryComponents(areas[i]);
    const float* o = &out[i * 3 * kComponents];
    FloatScale vec;
    for (size_t k = 0; k < kComponents; ++k) {
      std::string what = "config " + std::to_string(i) + " component " + std::to_string(k);
      compareValue(t, o[3 * k], o[3 * k + 2], f[k], inputs[i], kGeometryUlps, i * 64 + k, what);
      const bool vector = (k >= 1 && k < 7) || (k >= 10 && k < 13);  // direction, normal, hit
      if (vector && (k == 1 || k == 4 || k == 10)) vec = vectorScale(f, k, inputs[i], i * 64);
      compareDerivative(t, o[3 * k + 1], f[k], inputs[i], kGeometryUlps, i * 64 + k, what, vector ? &vec : nullptr);
    }
    // The ray-form hit: the GPU against the double closed form (float error only), and the closed
    // form against re-intersection (truncation only): together they pin down the derivation.
    for (int k = 0; k < 3; ++k) {
      const Input& in = inputs[i];
      FloatScale s = floatScale(f[10 + k], in.x, in.tangent, in.groups, in.frozen, kStep, i * 64 + 32 + k);
      double tol = kGeometryUlps * kUnitRoundoff * (s.terms + s.conditioning);
      ++hitClosed.compared;
      if (!(std::abs(o[3 * (10 + k) + 1] - closedForm[i][k]) <= tol) && ++hitClosed.failed <= kMaxReported)
        ADD_FAILURE() << "config " << i << " hit component " << k << ": gpu " << o[3 * (10 + k) + 1]
                      << " closed form " << closedForm[i][k] << " tolerance " << tol;
      FiniteDifference fd = centralDifference(f[10 + k], in.x, in.tangent, kStep);
      ++closedFd.compared;
      // Double rounding: the hit's coordinates come from differences of O(1) numbers (o + t w), so
      // the differences at step 2^-15 carry ~1e-12 relative to the derivative's scale; 1e-9 bounds it.
      if (!fd.smooth || !(std::abs(fd.derivative - exactClosedForm[i][k]) <= fd.truncation + 1e-9 * (s.terms + s.conditioning))) {
        if (++closedFd.failed <= kMaxReported)
          ADD_FAILURE() << "config " << i << " hit component " << k << ": closed form " << exactClosedForm[i][k]
                        << " re-intersection fd " << fd.derivative << " truncation " << fd.truncation;
      }
    }
  }
  std::printf("[ grad ] geometry: %zu configurations with |cos| < 1e-3 (the abs kink)\n", grazingCos);
  hitClosed.print();
  closedFd.print();
  EXPECT_EQ(hitClosed.failed, 0u);
  EXPECT_EQ(closedFd.failed, 0u);
  expectFewExclusions(t, 0.01);
}

// ---- Gates ----------------------------------------------------------------------------------------

std::vector<GateCase> gateCases() {
  std::vector<GateCase> cases = representativeGates();
  cases.push_back({"steady", Gate{}});
  return cases;
}

class GradGate : public ::testing::TestWithParam<GateCase> {};

TEST_P(GradGate, WeightDerivativesMatchFiniteDifferences) {
  const Gate& gate = GetParam().gate;
  constexpr uint32_t kCount = 8192;
  std::mt19937_64 rng(13);
  const double lo = gate.type == GateType::Steady ? 0.0 : gate.supportMin() - 0.5;
  const double hi = gate.type == GateType::Steady ? 10.0 : gate.supportMax() + 0.5;
  std::vector<double> special = gate.jumpLocations();
  struct In {
    float length, rate;
    uint32_t layer;
    float centreRate;
  };
  std::vector<In> in(kCount);
  for (uint32_t i = 0; i < kCount; ++i) {
    in[i].length = float(i < special.size() ? special[i] : uniform(rng, lo, hi));
    in[i].rate = float(uniform(rng, -2, 2));
    in[i].layer = gate.layers() > 1 ? uint32_t(rng() % gate.layers()) : 0;
    in[i].centreRate = float(uniform(rng, -1, 1));
  }
  const Scene scene = sceneWithGate(gate);
  std::vector<float> out = runKernel<float>("dual_gate", in, 8 * kCount, kCount, &scene);
  Tally t{std::string("gate ") + GetParam().name};
  for (uint32_t i = 0; i < kCount; ++i) {
    const float* o = &out[8 * i];
    const uint32_t layer = in[i].layer;
    // x = [L, shift of the gate]; W(L; shift) = gate.shifted(shift).weight(L).
    ScalarFunction f = [&gate, layer](const std::vector<double>& x) { return gate.shifted(x[1]).weight(x[0], layer); };
    Input lengthOnly{{in[i].length, 0.0}, {in[i].rate, 0.0}, {0, 1}, {false, false}};
    Input centreOnly{{in[i].length, 0.0}, {0.0, 1.0}, {0, 1}, {false, false}};
    Input both{{in[i].length, 0.0}, {in[i].rate, in[i].centreRate}, {0, 1}, {false, false}};
    std::string what = "L = " + std::to_string(in[i].length) + " layer " + std::to_string(layer);
    compareValue(t, o[0], o[2], f, lengthOnly, kOpsUlps, 3 * i, what);
    compareValue(t, o[5], o[2], f, lengthOnly, kOpsUlps, 3 * i, what + " (with centre rate)");
    compareDerivative(t, o[1], f, lengthOnly, kOpsUlps, 3 * i, what + " dW/dL L'");
    compareDerivative(t, o[3], f, centreOnly, kOpsUlps, 3 * i + 1, what + " dW/dcentre");
    compareDerivative(t, o[4], f, both, kOpsUlps, 3 * i + 2, what + " W'(L)(L' - c')");
    // Standard NEE leaves connections the gate does not reach untraced: none may have a weight
    // or a derivative.
    if (o[6] == 0.0f)
      for (size_t k : {0, 1, 2, 3, 4, 5}) EXPECT_EQ(o[k], 0.0f) << what << ": the gate does not reach it, output " << k;
  }
  // It is reached somewhere, and a NaN length is (the accumulators count it as non-finite).
  uint32_t reached = 0;
  for (uint32_t i = 0; i < kCount; ++i) reached += out[8 * i + 6] == 1.0f;
  EXPECT_GT(reached, 0u);
  in.assign(1, In{std::numeric_limits<float>::quiet_NaN(), 0.0f, 0u, 0.0f});
  EXPECT_EQ(runKernel<float>("dual_gate", in, 8, 1, &scene)[6], 1.0f) << "a NaN length";
  // Box and bins gates are flat: every comparison checks an exact zero away from the edges;
  // stencils on an edge (1e-4 of the support per edge) or the gaussian cut-off are excluded.
  expectFewExclusions(t, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Gates, GradGate, ::testing::ValuesIn(gateCases()),
                         [](const ::testing::TestParamInfo<GateCase>& info) { return std::string(info.param.name); });

// ---- BSDF -----------------------------------------------------------------------------------------

// Rotates w by a random angle of scale `angle` about a random axis.
glm::dvec3 perturb(const glm::dvec3& w, double angle, std::mt19937_64& rng) {
  glm::dvec3 axis = glm::normalize(glm::cross(w, randomUnit(rng)));
  double a = angle * std::normal_distribution<double>()(rng);
  return w * std::cos(a) + glm::cross(axis, w) * std::sin(a) + axis * glm::dot(axis, w) * (1 - std::cos(a));
}

// A float tangent perpendicular to the unit vector w (dNormalize's outputs are), of size up to 1.
glm::dvec3 tangentOf(const glm::dvec3& w, std::mt19937_64& rng) {
  glm::dvec3 t = randomVector(rng, -1, 1);
  return glm::dvec3(glm::vec3(t - w * glm::dot(w, t)));
}

// A material scalar on the 2^-20 grid, and a tangent in quarters: x +- k t (k = h, h/2, h/4, all
// powers of two) is then a float, so the twin (which takes float materials) sees the exact stencil.
double onGrid(double x) { return std::ldexp(std::round(std::ldexp(x, 20)), -20); }
double quarterTangent(std::mt19937_64& rng) { return double(int(rng() % 9) - 4) / 4.0; }

struct BsdfIn {
  uint32_t type;
  float albedo, roughness, ior, dAlbedo, dRoughness, dIor, pad;
  float v[6][4];  // n, dn, wi, dwi, wo, dwo
};
static_assert(sizeof(BsdfIn) == 128);

TEST(GradFunctions, BsdfEvalDualMatchesFiniteDifferences) {
  constexpr uint32_t kCount = 3 * 6000;
  std::mt19937_64 rng(14);
  std::vector<BsdfIn> in(kCount);
  std::vector<Input> inputs(kCount);
  for (uint32_t i = 0; i < kCount; ++i) {
    BsdfIn& b = in[i];
    b.type = i % 3;
    b.albedo = float(onGrid(uniform(rng, 0.05, 0.95)));
    double r = uniform(rng, 0.0, 1.0);
    // Mostly differentiable roughness; some above 1 and below 1e-3 where the clamp holds it (derivative 0).
    b.roughness = float(onGrid(r < 0.85 ? uniform(rng, 0.02, 1.0) : r < 0.95 ? uniform(rng, 1.01, 1.5) : uniform(rng, 1e-4, 9e-4)));
    b.ior = float(onGrid(rng() % 4 == 0 ? uniform(rng, 0.4, 0.9) : uniform(rng, 1.1, 2.5)));
    b.dAlbedo = float(quarterTangent(rng));
    b.dRoughness = float(quarterTangent(rng));
    b.dIor = float(quarterTangent(rng));
    b.pad = 0;
    glm::dvec3 n = randomUnit(rng), wi = randomUnit(rng);
    glm::dvec3 side = glm::dot(n, wi) >= 0 ? n : -n;
    glm::dvec3 wo;
    int mode = int(rng() % 3);
    if (mode == 0) {
      wo = randomUnit(rng);
    } else {
      // Near the mirror or the refracted direction, where microfacet lobes take their large values.
      glm::dvec3 target = 2 * glm::dot(side, wi) * side - wi;
      if (mode == 2 && b.type == gpu::kMaterialDielectric) {
        double eta = glm::dot(n, wi) >= 0 ? b.ior : 1.0 / b.ior;
        glm::dvec3 t = glm::refract(-wi, side, 1.0 / eta);
        if (glm::length(t) > 0.5) target = t;
      }
      wo = glm::dvec3(glm::vec3(glm::normalize(perturb(target, 2.0 * std::clamp(double(b.roughness), 1e-3, 1.0), rng))));
    }
    glm::dvec3 vecs[6] = {n, tangentOf(n, rng), wi, tangentOf(wi, rng), wo, tangentOf(wo, rng)};
    for (int k = 0; k < 6; ++k) {
      for (int c = 0; c < 3; ++c) b.v[k][c] = float(vecs[k][c]);
      b.v[k][3] = 0;
    }
    Input& x = inputs[i];
    for (int k = 0; k < 6; k += 2) {
      push(x.x, vecs[k]);
      push(x.tangent, vecs[k + 1]);
    }
    x.x.insert(x.x.end(), {b.albedo, b.roughness, b.ior});
    x.tangent.insert(x.tangent.end(), {b.dAlbedo, b.dRoughness, b.dIor});
    x.groups = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 4, 5};
    x.frozen = {false, false, false, false, false, false, false, false, false, true, true, true};
  }
  std::vector<float> out = runKernel<float>("dual_bsdf", in, 4 * kCount, kCount);
  const char* names[3] = {"bsdf diffuse", "bsdf conductor", "bsdf dielectric"};
  std::vector<Tally> tallies = {{names[0]}, {names[1]}, {names[2]}};
  size_t nonzero[3] = {0, 0, 0};
  for (uint32_t i = 0; i < kCount; ++i) {
    const BsdfIn& b = in[i];
    const uint32_t type = b.type;
    ScalarFunction f = [type](const std::vector<double>& x) {
      gpu::GpuMaterial m{type, float(x[9]), float(x[10]), float(x[11])};
      return bsdfEvalReference(m, at(x, 0), at(x, 3), at(x, 6));
    };
    const float* o = &out[4 * i];
    Tally& t = tallies[type];
    if (o[0] != 0.0f) ++nonzero[type];
    std::string what = "config " + std::to_string(i);
    compareValue(t, o[0], o[2], f, inputs[i], kBsdfUlps, i, what);
    // Where the float primal itself cannot be trusted (tests/gpu_bsdf.cpp's criterion: near the
    // critical angle or the horizon its sensitivity is unbounded), neither can its derivative.
    gpu::GpuMaterial m{type, b.albedo, b.roughness, b.ior};
    const Input& x = inputs[i];
    double kappa = bsdfSensitivityReference(m, at(x.x, 0), at(x.x, 3), at(x.x, 6), true, i);
    if (!(bsdfFloatTolerance(kappa) <= 1e-2)) {
      ++t.illConditioned;
      continue;
    }
    compareDerivative(t, o[1], f, x, kBsdfUlps, i, what);
  }
  for (int k = 0; k < 3; ++k) {
    std::printf("[ grad ] %s: %zu of %u configurations with f != 0\n", names[k], nonzero[k], kCount / 3);
    // Most configurations must exercise a non-zero lobe, or the comparisons prove little.
    EXPECT_GT(nonzero[k], size_t(kCount / 3 / 4)) << names[k];
    expectFewExclusions(tallies[k], 0.05);
  }
}

}  // namespace
}  // namespace vktg::test
