// Double-precision twin of shaders/lib/ellipsoid.glsl; see ellipsoid_reference.h and the shader
// header for the mathematics. Keep the two in step: the GPU tests compare them element by element.
#include "support/ellipsoid_reference.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace vktg::test {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void frameFrom(dvec3 u1, dvec3& u2, dvec3& u3) {
  double sgn = u1.z >= 0.0 ? 1.0 : -1.0;
  double p = -1.0 / (sgn + u1.z);
  double q = u1.x * u1.y * p;
  u2 = dvec3(1.0 + sgn * u1.x * u1.x * p, sgn * q, -sgn * u1.x);
  u3 = dvec3(q, sgn + u1.y * u1.y * p, -u1.y);
}

double wrapAngle(double phi) {
  double w = phi - kTwoPi * std::floor(phi / kTwoPi);
  return w >= kTwoPi ? 0.0 : w;
}

dvec3 baryAt(const EllipseArcsRef& arcs, double phi) {
  return arcs.baryAlpha + arcs.baryBeta * std::cos(phi) + arcs.baryGamma * std::sin(phi);
}

bool insideAt(const EllipseArcsRef& arcs, double phi) {
  dvec3 l = baryAt(arcs, phi);
  return l.x >= 0.0 && l.y >= 0.0 && l.z >= 0.0;
}

}  // namespace

double pathLengthRef(dvec3 f1, dvec3 f2, dvec3 x) { return glm::length(x - f1) + glm::length(x - f2); }

bool ellipseOnTriangleRef(dvec3 f1, dvec3 f2, double sPrime, const RefTriangle& tri, EllipseArcsRef& arcs) {
  arcs = EllipseArcsRef{};
  arcs.origin = tri.p0;
  dvec3 d = f2 - f1;
  double dist = glm::length(d);
  if (!(sPrime > dist)) return false;
  double a = 0.5 * sPrime;
  double c = 0.5 * dist;
  double b = std::sqrt((a - c) * (a + c));
  dvec3 u1 = dist > 0.0 ? d / dist : dvec3(0.0, 0.0, 1.0);
  dvec3 u2, u3;
  frameFrom(u1, u2, u3);

  dvec3 e01 = tri.p1 - tri.p0;
  dvec3 e02 = tri.p2 - tri.p0;
  dvec3 n = glm::cross(e01, e02);
  double nn = glm::dot(n, n);
  if (!(nn > 0.0)) return false;
  dvec3 nUnit = n / std::sqrt(nn);
  dvec3 m = (f1 - tri.p0) + 0.5 * d;
  dvec3 np(a * glm::dot(nUnit, u1), b * glm::dot(nUnit, u2), b * glm::dot(nUnit, u3));
  double npLen = glm::length(np);
  if (!(npLen > 0.0)) return false;
  double t = -glm::dot(nUnit, m) / npLen;
  double at = std::abs(t);
  if (!(at < 1.0)) return false;
  double r = std::sqrt((1.0 - at) * (1.0 + at));
  dvec3 nh = np / npLen;
  dvec3 e1, e2;
  frameFrom(nh, e1, e2);
  dvec3 yc = t * nh;
  auto mapM = [&](dvec3 y) { return a * y.x * u1 + b * (y.y * u2 + y.z * u3); };
  arcs.centre = m + mapM(yc);
  arcs.axisA = r * mapM(e1);
  arcs.axisB = r * mapM(e2);
  arcs.ratioScale = 0.5 / npLen;

  dvec3 nOver = n / nn;
  auto bary = [&](dvec3 q) { return dvec2(glm::dot(glm::cross(q, e02), nOver), glm::dot(glm::cross(e01, q), nOver)); };
  dvec2 alpha = bary(arcs.centre), beta = bary(arcs.axisA), gamma = bary(arcs.axisB);
  arcs.baryAlpha = dvec3(1.0 - alpha.x - alpha.y, alpha.x, alpha.y);
  arcs.baryBeta = dvec3(-beta.x - beta.y, beta.x, beta.y);
  arcs.baryGamma = dvec3(-gamma.x - gamma.y, gamma.x, gamma.y);

  std::vector<double> roots;
  for (int i = 0; i < 3; ++i) {
    double al = arcs.baryAlpha[i];
    double rho = std::hypot(arcs.baryBeta[i], arcs.baryGamma[i]);
    if (rho > std::abs(al)) {
      dvec2 dir = dvec2(arcs.baryBeta[i], arcs.baryGamma[i]) / rho;
      dvec2 perp(-dir.y, dir.x);
      double h = std::sqrt((rho - std::abs(al)) * (rho + std::abs(al))) / rho;
      dvec2 foot = (-al / rho) * dir;
      dvec2 q0 = foot - h * perp, q1 = foot + h * perp;
      roots.push_back(wrapAngle(std::atan2(q0.y, q0.x)));
      roots.push_back(wrapAngle(std::atan2(q1.y, q1.x)));
    }
  }
  if (roots.empty()) {
    if (insideAt(arcs, 0.0)) {
      arcs.count = 1;
      arcs.arcLength[0] = kTwoPi;
    }
  } else {
    std::sort(roots.begin(), roots.end());
    size_t k = roots.size();
    bool prevKept = false, firstKept = false, seenFirst = false;
    for (size_t i = 0; i < k; ++i) {
      double start = roots[i];
      double len = (i + 1 < k ? roots[i + 1] : roots[0] + kTwoPi) - start;
      if (!(len > 0.0)) continue;
      bool kept = insideAt(arcs, start + 0.5 * len);
      if (!seenFirst) {
        firstKept = kept;
        seenFirst = true;
      }
      if (kept) {
        if (prevKept) {
          arcs.arcLength[arcs.count - 1] += len;
        } else if (arcs.count < 3) {
          arcs.arcStart[arcs.count] = start;
          arcs.arcLength[arcs.count] = len;
          ++arcs.count;
        }
      }
      prevKept = kept;
    }
    if (prevKept && firstKept && arcs.count > 1) {
      int last = arcs.count - 1;
      arcs.arcStart[0] = arcs.arcStart[last];
      arcs.arcLength[0] += arcs.arcLength[last];
      arcs.arcStart[last] = 0.0;
      arcs.arcLength[last] = 0.0;
      arcs.count = last;
    }
  }
  for (int i = 0; i < arcs.count; ++i) {
    arcs.total += arcs.arcLength[i];
    double speedSum = 0.0;
    for (int j = 0; j < kEllipseWeightNodesRef; ++j)
      speedSum += ellipseSpeedRef(arcs, arcs.arcStart[i] + (j + 0.5) / kEllipseWeightNodesRef * arcs.arcLength[i]);
    arcs.weight += arcs.arcLength[i] * speedSum / kEllipseWeightNodesRef;
  }
  return arcs.count > 0 && arcs.weight > 0.0 && arcs.total > 0.0;
}

double ellipseArcPhiRef(const EllipseArcsRef& arcs, double u) {
  double target = u * arcs.total;
  for (int i = 0; i < arcs.count; ++i) {
    if (target < arcs.arcLength[i] || i + 1 == arcs.count) return arcs.arcStart[i] + std::min(target, arcs.arcLength[i]);
    target -= arcs.arcLength[i];
  }
  return 0.0;
}

dvec3 ellipsePointRef(const EllipseArcsRef& arcs, double phi) {
  return arcs.origin + (arcs.centre + arcs.axisA * std::cos(phi) + arcs.axisB * std::sin(phi));
}

dvec2 ellipseBarycentricsRef(const EllipseArcsRef& arcs, double phi) {
  dvec3 l = glm::max(baryAt(arcs, phi), dvec3(0.0));
  return dvec2(l.y, l.z) / std::max(l.x + l.y + l.z, 1e-300);
}

double ellipseSpeedRef(const EllipseArcsRef& arcs, double phi) {
  return glm::length(arcs.axisB * std::cos(phi) - arcs.axisA * std::sin(phi));
}

double ellipseCoareaRatioRef(const EllipseArcsRef& arcs, dvec3 f1, dvec3 f2, dvec3 x) {
  return glm::length(x - f1) * glm::length(x - f2) * arcs.ratioScale;
}

double projectedGradientRef(dvec3 f1, dvec3 f2, dvec3 x, dvec3 normal) {
  dvec3 g1 = x - f1, g2 = x - f2;
  double l1 = glm::length(g1), l2 = glm::length(g2);
  dvec3 grad = (l1 > 0.0 ? g1 / l1 : dvec3(0.0)) + (l2 > 0.0 ? g2 / l2 : dvec3(0.0));
  dvec3 nUnit = glm::normalize(normal);
  return glm::length(grad - glm::dot(grad, nUnit) * nUnit);
}

double ellipsoidDensityRef(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double sPrime, size_t tri,
                           dvec3 x) {
  double sum = 0.0;
  EllipseArcsRef target;
  bool found = false;
  for (size_t i = 0; i < triangles.size(); ++i) {
    EllipseArcsRef arcs;
    if (!ellipseOnTriangleRef(f1, f2, sPrime, triangles[i], arcs)) continue;
    sum += arcs.weight;
    if (i == tri) {
      target = arcs;
      found = true;
    }
  }
  if (!found || !(sum > 0.0)) return 0.0;
  return (target.weight / sum) / (target.total * ellipseCoareaRatioRef(target, f1, f2, x));
}

double ellipsoidBoxImportanceRef(dvec3 lo, dvec3 hi, dvec3 f1, dvec3 f2, double sPrime) {
  double lower = glm::length(glm::max(glm::max(lo - f1, f1 - hi), dvec3(0.0))) +
                 glm::length(glm::max(glm::max(lo - f2, f2 - hi), dvec3(0.0)));
  double upper = 0.0;
  for (int i = 0; i < 8; ++i) {
    dvec3 q((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    upper = std::max(upper, glm::length(q - f1) + glm::length(q - f2));
  }
  if (!(lower * (1.0 - 1e-6) <= sPrime && sPrime <= upper * (1.0 + 1e-6))) return 0.0;
  double span = upper - lower;
  double tent = span > 0.0 ? std::clamp(2.0 * std::min(sPrime - lower, upper - sPrime) / span, 0.0, 1.0) : 1.0;
  const double floor = 0.02;  // kEllipsoidTentFloor in the shader
  return std::max(glm::length(hi - lo), 1e-30) * (floor + tent);
}

double ellipsoidDescentProbabilityRef(const Bvh& bvh, std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2,
                                      double sPrime, size_t tri) {
  auto word = [](float f) { return std::bit_cast<uint32_t>(f); };
  double probability = 1.0;
  uint32_t index = 0;
  for (size_t level = 0; level < bvh.nodes.size(); ++level) {
    const gpu::GpuBvhNode& n = bvh.nodes[index];
    uint32_t count = word(n.rightMinCount.w), first = word(n.rightMaxFirst.w);
    if (count > 0) {
      double sum = 0.0, target = 0.0;
      for (uint32_t i = first; i < first + count; ++i) {
        EllipseArcsRef arcs;
        if (!ellipseOnTriangleRef(f1, f2, sPrime, triangles[i], arcs)) continue;
        sum += arcs.weight;
        if (i == tri) target = arcs.weight;
      }
      return sum > 0.0 ? probability * target / sum : 0.0;
    }
    double left = ellipsoidBoxImportanceRef(dvec3(n.leftMinLeftIndex), dvec3(n.leftMaxRightIndex), f1, f2, sPrime);
    double right = ellipsoidBoxImportanceRef(dvec3(n.rightMinCount), dvec3(n.rightMaxFirst), f1, f2, sPrime);
    bool goRight = tri >= first;
    if (!(left + right > 0.0)) return 0.0;
    probability *= (goRight ? right : left) / (left + right);
    index = word(goRight ? n.leftMaxRightIndex.w : n.leftMinLeftIndex.w);
  }
  return 0.0;
}

double ellipsoidDescentDensityRef(const Bvh& bvh, std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2,
                                  double sPrime, size_t tri, dvec3 x) {
  EllipseArcsRef arcs;
  if (!ellipseOnTriangleRef(f1, f2, sPrime, triangles[tri], arcs)) return 0.0;
  double p = ellipsoidDescentProbabilityRef(bvh, triangles, f1, f2, sPrime, tri);
  return p > 0.0 ? p / (arcs.total * ellipseCoareaRatioRef(arcs, f1, f2, x)) : 0.0;
}

bool sampleEllipsoidRef(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double sPrime, double uPick,
                        double uPhi, EllipsoidSampleRef& out) {
  std::vector<EllipseArcsRef> all(triangles.size());
  double sum = 0.0;
  for (size_t i = 0; i < triangles.size(); ++i)
    if (ellipseOnTriangleRef(f1, f2, sPrime, triangles[i], all[i])) sum += all[i].weight;
  if (!(sum > 0.0)) return false;
  double target = uPick * sum;
  size_t pick = triangles.size();
  for (size_t i = 0; i < triangles.size(); ++i) {
    if (all[i].weight <= 0.0) continue;
    pick = i;
    if (target < all[i].weight) break;
    target -= all[i].weight;
  }
  const EllipseArcsRef& arcs = all[pick];
  double phi = ellipseArcPhiRef(arcs, uPhi);
  out.triangle = pick;
  out.position = ellipsePointRef(arcs, phi);
  out.barycentrics = ellipseBarycentricsRef(arcs, phi);
  out.weight = (sum / arcs.weight) * arcs.total * ellipseCoareaRatioRef(arcs, f1, f2, out.position);
  return true;
}

namespace {

// Minimiser of a convex function on [lo, hi] by golden-section search.
template <class F>
double convexArgMin(F f, double lo, double hi) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 90 && hi - lo > 0.0; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return 0.5 * (lo + hi);
}

// Crossing of f(x) = s between `in` (f <= s) and `out` (f > s), by bisection.
template <class F>
double crossing(F f, double s, double in, double out) {
  for (int i = 0; i < 80; ++i) {
    double mid = 0.5 * (in + out);
    (f(mid) <= s ? in : out) = mid;
  }
  return 0.5 * (in + out);
}

// Length (in u) of {u in [0, uMax] : f(u) <= s} for convex f.
template <class F>
double sublevelLength(F f, double s, double uMax) {
  if (uMax <= 0.0) return 0.0;
  double uStar = convexArgMin(f, 0.0, uMax);
  if (f(uStar) > s) return 0.0;
  double lo = f(0.0) <= s ? 0.0 : crossing(f, s, uStar, 0.0);
  double hi = f(uMax) <= s ? uMax : crossing(f, s, uStar, uMax);
  return hi - lo;
}

}  // namespace

double shellAreaOnTriangle(const RefTriangle& tri, dvec3 f1, dvec3 f2, double s, int rows) {
  dvec3 e01 = tri.p1 - tri.p0, e02 = tri.p2 - tri.p0;
  double jac = glm::length(glm::cross(e01, e02));
  auto rowFn = [&](double v) {
    return [&, v](double u) { return pathLengthRef(f1, f2, tri.p0 + u * e01 + v * e02); };
  };
  // min over a row is convex in v (partial minimum of a convex function over a convex set).
  auto rowMin = [&](double v) {
    auto f = rowFn(v);
    return f(convexArgMin(f, 0.0, 1.0 - v));
  };
  double vStar = convexArgMin(rowMin, 0.0, 1.0);
  if (rowMin(vStar) > s) return 0.0;
  double v0 = rowMin(0.0) <= s ? 0.0 : crossing(rowMin, s, vStar, 0.0);
  double v1 = rowMin(1.0) <= s ? 1.0 : crossing(rowMin, s, vStar, 1.0);
  double mid = 0.5 * (v0 + v1), half = 0.5 * (v1 - v0);
  double sum = 0.0;
  for (int i = 0; i < rows; ++i) {
    double theta = (i + 0.5) / rows * std::numbers::pi;
    double v = mid - half * std::cos(theta);
    sum += sublevelLength(rowFn(v), s, 1.0 - v) * half * std::sin(theta);
  }
  return jac * sum * std::numbers::pi / rows;
}

double shellAreaDerivative(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double s, double h, int rows) {
  double sum = 0.0;
  for (const RefTriangle& tri : triangles)
    sum += shellAreaOnTriangle(tri, f1, f2, s + h, rows) - shellAreaOnTriangle(tri, f1, f2, s - h, rows);
  return sum / (2.0 * h);
}

}  // namespace vktg::test
