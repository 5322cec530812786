// Double-precision CPU twin of shaders/lib/ellipsoid.glsl (ellipsoidal path connections,
// THEORY.md §4): the same mathematics step by step, used as the reference of the GPU tests and of
// derivative tests. Plus independent ground truth that shares nothing with it: the area of
// {x on a triangle : L(x) <= s} by quadrature (its derivative in s is what the connection's
// weights must average to).
// Units: metres for positions and lengths, radians for angles.
#pragma once
#include <array>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/bvh.h"

namespace vktg::test {

using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;

// Same count as kEllipseWeightNodes in the shader: the selection weight must match.
inline constexpr int kEllipseWeightNodesRef = 4;

struct RefTriangle {
  dvec3 p0, p1, p2;
};

// One triangle's clipped conic: x(phi) = origin + centre + axisA cos(phi) + axisB sin(phi).
struct EllipseArcsRef {
  dvec3 origin{0.0}, centre{0.0}, axisA{0.0}, axisB{0.0};
  dvec3 baryAlpha{0.0}, baryBeta{0.0}, baryGamma{0.0};  // (l0, l1, l2)(phi)
  std::array<double, 3> arcStart{}, arcLength{};
  int count = 0;
  double total = 0.0;       // Phi_t
  double weight = 0.0;      // w_t, the selection weight (estimated curve length)
  double ratioScale = 0.0;  // |n| / (2 |M^T n|)
};

// False when the shell misses the triangle (or s' <= |f2 - f1|); never NaN.
bool ellipseOnTriangleRef(dvec3 f1, dvec3 f2, double sPrime, const RefTriangle& tri, EllipseArcsRef& arcs);
double ellipseArcPhiRef(const EllipseArcsRef& arcs, double u);
dvec3 ellipsePointRef(const EllipseArcsRef& arcs, double phi);
dvec2 ellipseBarycentricsRef(const EllipseArcsRef& arcs, double phi);
double ellipseSpeedRef(const EllipseArcsRef& arcs, double phi);
// |x'(phi)| / |P_T grad L| at x on the curve, closed form (see the shader header).
double ellipseCoareaRatioRef(const EllipseArcsRef& arcs, dvec3 f1, dvec3 f2, dvec3 x);

// |P_T grad L| at x on a triangle with unit normal `normal`, computed directly (the definition,
// for checking the closed form away from tangency).
double projectedGradientRef(dvec3 f1, dvec3 f2, dvec3 x, dvec3 normal);
double pathLengthRef(dvec3 f1, dvec3 f2, dvec3 x);

// 1 / weight of a sample at x on triangles[tri] (pdf_l * |P_T grad L|), 0 where none.
double ellipsoidDensityRef(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double sPrime, size_t tri,
                           dvec3 x);

// The stochastic BVH descent (kEllipsoidDescend): probability that it picks triangles[tri], with
// `triangles` in the leaf order of `bvh` (the host builder's tree the GPU gets). 0 where it cannot.
double ellipsoidDescentProbabilityRef(const Bvh& bvh, std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2,
                                      double sPrime, size_t tri);
// The shader's per-box descent weight (ellipsoidBoxImportance), in double precision.
double ellipsoidBoxImportanceRef(dvec3 lo, dvec3 hi, dvec3 f1, dvec3 f2, double sPrime);
// 1 / weight of a descent sample at x on triangles[tri], 0 where none.
double ellipsoidDescentDensityRef(const Bvh& bvh, std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2,
                                  double sPrime, size_t tri, dvec3 x);

struct EllipsoidSampleRef {
  size_t triangle = 0;
  dvec3 position{0.0};
  dvec2 barycentrics{0.0};
  double weight = 0.0;
};
// Picks a triangle by the CDF of w_t with uPick, phi with uPhi. False when nothing is met.
bool sampleEllipsoidRef(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double sPrime, double uPick,
                        double uPhi, EllipsoidSampleRef& out);

// Independent ground truth: area of {x on tri : L(x) <= s}. Rows of the triangle parallel to
// p0->p1; on each row L is convex, so its sublevel set is one interval found by bisection; rows
// are placed with a cosine map over the range of rows that meet the set, which removes the
// square-root behaviour of the row length at the ends.
double shellAreaOnTriangle(const RefTriangle& tri, dvec3 f1, dvec3 f2, double s, int rows);
// d/ds of the total area over `triangles`, central difference with step h.
double shellAreaDerivative(std::span<const RefTriangle> triangles, dvec3 f1, dvec3 f2, double s, double h, int rows);

}  // namespace vktg::test
