#include "support/dual_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace vktg::test {

double segmentLengthReference(const glm::dvec3& from, const glm::dvec3& to) { return glm::length(to - from); }

glm::dvec3 segmentDirectionReference(const glm::dvec3& from, const glm::dvec3& to) {
  return (to - from) / glm::length(to - from);
}

glm::dvec3 triangleNormalReference(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2) {
  return glm::normalize(glm::cross(p1 - p0, p2 - p0));
}

double triangleAreaReference(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2) {
  return 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
}

std::optional<RayHitReference> intersectPlaneReference(const glm::dvec3& o, const glm::dvec3& w, const glm::dvec3& p0,
                                                       const glm::dvec3& p1, const glm::dvec3& p2) {
  glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
  glm::dvec3 pv = glm::cross(w, e2);
  double det = glm::dot(e1, pv);
  if (det == 0.0) return std::nullopt;
  double inv = 1.0 / det;
  glm::dvec3 s = o - p0;
  glm::dvec3 qv = glm::cross(s, e1);
  return RayHitReference{glm::dot(e2, qv) * inv, glm::dot(s, pv) * inv, glm::dot(w, qv) * inv};
}

glm::dvec3 rayHitVelocityReference(const glm::dvec3& w, const glm::dvec3& p0, const glm::dvec3& p1,
                                   const glm::dvec3& p2, const glm::dvec3& v0, const glm::dvec3& v1,
                                   const glm::dvec3& v2, double u, double v) {
  glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
  glm::dvec3 xdot = (1.0 - u - v) * v0 + u * v1 + v * v2;
  return w * (glm::dot(n, xdot) / glm::dot(n, w));
}


namespace {

std::vector<double> along(const std::vector<double>& x, const std::vector<double>& t, double k) {
  std::vector<double> y(x.size());
  for (size_t i = 0; i < x.size(); ++i) y[i] = x[i] + k * t[i];
  return y;
}

double difference(const ScalarFunction& f, const std::vector<double>& x, const std::vector<double>& t, double k,
                  double& magnitude) {
  double plus = f(along(x, t, k)), minus = f(along(x, t, -k));
  magnitude = std::max({magnitude, std::abs(plus), std::abs(minus)});
  return (plus - minus) / (2.0 * k);
}

}  // namespace

FiniteDifference centralDifference(const ScalarFunction& f, const std::vector<double>& x,
                                   const std::vector<double>& tangent, double h) {
  double magnitude = std::abs(f(x));
  double d1 = difference(f, x, tangent, h, magnitude);
  double d2 = difference(f, x, tangent, h / 2, magnitude);
  double d4 = difference(f, x, tangent, h / 4, magnitude);
  // Each double evaluation errs by at most ~1e3 ulps of the largest value (generous for the twins'
  // chains of some hundred operations); the difference at step h/4 divides that by h/2.
  double noise = 1e3 * std::numeric_limits<double>::epsilon() * magnitude / (h / 2);
  // One-sided slopes differ by f'' k for smooth f, by the slope's jump at a kink on x: their
  // difference over k (the second difference) halves with k only when f is smooth at x.
  double f0 = f(x);
  double curve2 = (f(along(x, tangent, h / 2)) + f(along(x, tangent, -h / 2)) - 2 * f0) / (h / 2);
  double curve4 = (f(along(x, tangent, h / 4)) + f(along(x, tangent, -h / 4)) - 2 * f0) / (h / 4);
  FiniteDifference r;
  if (!std::isfinite(d1) || !std::isfinite(d2) || !std::isfinite(d4) || !std::isfinite(curve2) ||
      !std::isfinite(curve4)) {
    r.smooth = false;
    return r;
  }
  r.smooth = std::abs(d2 - d4) <= 0.5 * std::abs(d1 - d2) + 2 * noise &&
             std::abs(curve4) <= 0.75 * std::abs(curve2) + 4 * noise;
  r.derivative = d4 + (d4 - d2) / 3.0;
  r.truncation = std::abs(d4 - d2) + noise;
  return r;
}

FloatScale floatScale(const ScalarFunction& f, const std::vector<double>& x, const std::vector<double>& tangent,
                      const std::vector<int>& groups, const std::vector<bool>& frozen, double h, uint64_t seed) {
  FloatScale s;
  double base = centralDifference(f, x, tangent, h).derivative;
  std::set<int> ids(groups.begin(), groups.end());
  for (int g : ids) {
    std::vector<double> part(tangent.size(), 0.0);
    for (size_t i = 0; i < tangent.size(); ++i)
      if (groups[i] == g) part[i] = tangent[i];
    s.terms += std::abs(centralDifference(f, x, part, h).derivative);
  }
  std::mt19937_64 rng(seed);
  const double delta = std::ldexp(1.0, -20);
  // Values (trials 0, 1) and tangent components (trials 2, 3): a derivative is a sum of products of
  // tangent components with partial derivatives, and perturbing the tangent reveals those products'
  // magnitudes where they cancel (the part of a' across a in a normalisation, say).
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<double> y = x, t = tangent;
    std::vector<double>& moved = trial < 2 ? y : t;
    for (size_t i = 0; i < x.size(); ++i)
      if (!(trial < 2 && frozen[i])) moved[i] *= 1.0 + ((rng() & 1) ? delta : -delta);
    double d = centralDifference(f, y, t, h).derivative;
    s.conditioning = std::max(s.conditioning, std::abs(d - base) / delta);
  }
  return s;
}

double valueFloatScale(const ScalarFunction& f, const std::vector<double>& x, const std::vector<bool>& frozen,
                       uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double delta = std::ldexp(1.0, -20);
  const double base = f(x);
  double conditioning = 0.0;
  for (int trial = 0; trial < 2; ++trial) {
    std::vector<double> y = x;
    for (size_t i = 0; i < x.size(); ++i)
      if (!frozen[i]) y[i] *= 1.0 + ((rng() & 1) ? delta : -delta);
    conditioning = std::max(conditioning, std::abs(f(y) - base) / delta);
  }
  return std::abs(base) + conditioning;
}

}  // namespace vktg::test
