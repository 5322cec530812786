// The exact distance along a ray to a triangle's plane, for judging the triangle test's refined
// hit distance (docs/precision.md). Header-only: the CPU-only unit tests use it too.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "vktg/bvh.h"

namespace vktg::test {

// The bound the refinement guarantees (docs/precision.md), on the host and on any Vulkan device:
//   |t - t_exact| <= 1 ulp(t) + 2^-44 max_i |p_i - o| / (|d| sin theta)
// The ulp: the final rounding and the division's correction. The second term: double-float
// arithmetic keeps 2^-48 of the products it sums, whose size is set by the vertices' distance from
// the origin, and the plane distance they give is divided by the sine of the grazing angle theta
// (2^-44 leaves a factor 16 for the handful of products). For a hit at 5 m on a 10^4 m triangle
// seen at 1e-3 rad the second term is 3e-8 m, a tenth of an ulp.
inline constexpr double kHitDistanceUlps = 1.0;
inline constexpr double kDoubleFloatEps = 1.0 / 17592186044416.0;  // 2^-44

// (p0 - o) . n / (d . n), n = (p1 - p0) x (p2 - p0), in long double: differences of floats are
// exact there and the products lose 2^-64, a thousand times below a float's resolution even when
// the hit is 10^4 times closer than the vertices.
inline long double exactHitDistance(const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir) {
  using L = long double;
  L e1[3], e2[3], a[3], n[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = L(tri.p1[i]) - L(tri.p0[i]);
    e2[i] = L(tri.p2[i]) - L(tri.p0[i]);
    a[i] = L(tri.p0[i]) - L(origin[i]);
  }
  for (int i = 0; i < 3; ++i) n[i] = e1[(i + 1) % 3] * e2[(i + 2) % 3] - e1[(i + 2) % 3] * e2[(i + 1) % 3];
  L numerator = 0, denominator = 0;
  for (int i = 0; i < 3; ++i) {
    numerator += a[i] * n[i];
    denominator += L(dir[i]) * n[i];
  }
  return numerator / denominator;
}

// The spacing of floats at |t|.
inline double floatUlp(double t) {
  float f = std::fabs(float(t));
  return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

// The bound above for this ray and triangle, in units of t.
inline double hitDistanceBound(const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir, long double exact) {
  glm::dvec3 e1 = glm::dvec3(tri.p1) - glm::dvec3(tri.p0), e2 = glm::dvec3(tri.p2) - glm::dvec3(tri.p0);
  glm::dvec3 n = glm::cross(e1, e2), d(dir), o(origin);
  double sine = std::fabs(glm::dot(d, n)) / (glm::length(d) * glm::length(n));
  double far = std::max({glm::length(glm::dvec3(tri.p0) - o), glm::length(glm::dvec3(tri.p1) - o),
                         glm::length(glm::dvec3(tri.p2) - o)});
  return kHitDistanceUlps * floatUlp(double(exact)) + kDoubleFloatEps * far / (glm::length(d) * sine);
}

// |t - exact| relative to hitDistanceBound (at most 1 where the bound holds).
inline double hitDistanceErrorRatio(float t, const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir) {
  long double exact = exactHitDistance(tri, origin, dir);
  return double(std::fabs((long double)t - exact)) / hitDistanceBound(tri, origin, dir, exact);
}

// |t - exact| in ulps of the exact distance (what the tests print).
inline double hitDistanceErrorUlps(float t, long double exact) {
  return double(std::fabs((long double)t - exact)) / floatUlp(double(exact));
}

}  // namespace vktg::test
