// Double-precision CPU twins of shaders/lib/geometry_dual.glsl: the same geometry as plain values,
// which tests/grad_functions.cpp differentiates by central finite differences, plus the generic
// finite-difference machinery (step halving for a truncation bound and a smoothness test, input
// perturbation for the float conditioning) that those tests share.
// The BSDF's twin is tests/support/bsdf_reference.h; the gate's is Gate::weight (src/scene/gate.cpp).
#pragma once
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/gate.h"

namespace vktg::test {

// ---- Geometry twins ------------------------------------------------------------------------------
double segmentLengthReference(const glm::dvec3& from, const glm::dvec3& to);
glm::dvec3 segmentDirectionReference(const glm::dvec3& from, const glm::dvec3& to);
// normalize(cross(p1 - p0, p2 - p0)) and half its length before normalisation.
glm::dvec3 triangleNormalReference(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2);
double triangleAreaReference(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2);

struct RayHitReference {
  double t, u, v;
};
// Möller-Trumbore intersection of the ray o + t w (any t) with the triangle's plane, and the hit's
// barycentrics (no inside test: the caller checks them); nothing when the ray is parallel.
std::optional<RayHitReference> intersectPlaneReference(const glm::dvec3& o, const glm::dvec3& w, const glm::dvec3& p0,
                                                       const glm::dvec3& p1, const glm::dvec3& p2);
// Closed form of the ray-form hit's velocity: w (n . X') / (n . w), X' = the barycentric
// interpolation of the vertex velocities v0, v1, v2 at uv (derivation in geometry_dual.glsl).
glm::dvec3 rayHitVelocityReference(const glm::dvec3& w, const glm::dvec3& p0, const glm::dvec3& p1,
                                   const glm::dvec3& p2, const glm::dvec3& v0, const glm::dvec3& v1,
                                   const glm::dvec3& v2, double u, double v);

// ---- Finite differences ----------------------------------------------------------------------------
// A scalar function of a flat input vector (the values of the kernel's inputs, as doubles).
using ScalarFunction = std::function<double(const std::vector<double>&)>;

// Central differences of f along `tangent` at steps h, h/2, h/4: D(k) = (f(x + k t) - f(x - k t)) / 2k.
// For smooth f, D(k) = f' + c k^2 + O(k^4), so D(h/4) - D(h/2) = -(3/4) c (h/2)^2 and the Richardson
// value D(h/4) + (D(h/4) - D(h/2)) / 3 is f' + O(h^4); `truncation` = |D(h/4) - D(h/2)| plus the
// rounding noise of the double differences bounds its error with margin (3x the leading term).
// `smooth` is false when the successive differences do not shrink like k^2 (|D(h/2) - D(h/4)| >
// |D(h) - D(h/2)| / 2), or the second differences (f(x+k) + f(x-k) - 2 f(x)) / k not like k (a
// kink exactly at x, which the symmetric differences cannot see): a kink or jump inside the stencil
// (a branch, a clamp, a cut-off), where a finite difference does not measure the derivative. A kink
// or jump closer to x than h/4 always fails the test; one farther away leaves the Richardson value's
// error below `truncation`.
struct FiniteDifference {
  double derivative = 0.0;
  double truncation = 0.0;
  bool smooth = true;
};
FiniteDifference centralDifference(const ScalarFunction& f, const std::vector<double>& x,
                                   const std::vector<double>& tangent, double h);

// Scales of the float error of a forward-mode derivative computed in float32 (u = 2^-24 per operation):
//  terms        sum over input groups of |derivative along that group's part of the tangent|: the
//               magnitude of the terms the dual arithmetic adds, which its rounding is relative to;
//  conditioning change of the derivative per unit relative perturbation of the input values
//               and of the tangent components (measured: two random sign patterns each, of
//               relative size 2^-20): the rounding of intermediate values acts like such
//               perturbations. Inputs marked in `frozen` stay
//               put (values that the twin must receive exactly, such as float material scalars).
// A dual chain of N operations then errs by at most about N u (terms + conditioning).
struct FloatScale {
  double terms = 0.0;
  double conditioning = 0.0;
};
FloatScale floatScale(const ScalarFunction& f, const std::vector<double>& x, const std::vector<double>& tangent,
                      const std::vector<int>& groups, const std::vector<bool>& frozen, double h, uint64_t seed);

// The float error scale of a value f(x) computed in float32: |f| plus the change of f per unit
// relative perturbation of the non-frozen inputs (two random sign patterns of relative size
// 2^-20), the same measure as FloatScale's conditioning, for the value instead of the derivative.
// A chain of N operations errs by at most about N u times it, whatever the compiler fuses or
// reorders: a fused multiply-add rounds once where a multiply and an add round twice.
double valueFloatScale(const ScalarFunction& f, const std::vector<double>& x, const std::vector<bool>& frozen,
                       uint64_t seed);

}  // namespace vktg::test
