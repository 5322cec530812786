// Derivatives of the geometric pieces of a path (THEORY.md §2-3) for one derivative lane: a vertex
// is a Dual3 (position, dX/dθ) and everything below carries d/dθ along.
// Requires lib/common.glsl and lib/bindings.glsl (the gate reads `frame`) first.
//
//   Dual3 dBarycentric(Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv)
//       the material point X(p, θ) = (1-u-v) V0 + u V1 + v V2: position and velocity.
//   DualSegment dualSegment(Dual3 from, Dual3 to)
//       .len = |to - from| and .dir = the unit direction (to - from) / |to - from|.
//   Dual3 triangleNormalDual(Dual3 p0, Dual3 p1, Dual3 p2)
//       unit normal normalize(cross(p1 - p0, p2 - p0)) (the orientation of path.glsl's surfacePoint).
//   Dual triangleAreaDual(Dual3 p0, Dual3 p1, Dual3 p2)
//       |cross(p1 - p0, p2 - p0)| / 2.
//   Dual areaJacobianDual(Dual3 p0, Dual3 p1, Dual3 p2)
//       J = A(θ) / A(θ0) of the material-form change of variables: value 1, derivative dA/A.
//   Dual3 rayHitDual(vec3 dir, Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv)
//   Dual rayHitDistanceDual(vec3 origin, vec3 dir, Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv)
//       ray-form (pixel-space) primary hit: the fixed ray origin + t dir (dir unit) meets the moving
//       triangle; at θ0 it meets it at barycentrics uv. Returns the hit point (its velocity does not
//       depend on the origin) / the distance t.
//   Dual dAbsCos(Dual3 n, Dual3 w)
//       |n . w|, the cosine factor of a geometry term.
//   float gateWeightSlope(float len, uint layer)
//       W'(L) of gate layer `layer` (lib/gate.glsl's gateWeight): the smooth part only. Box and bins
//       gates are flat away from their jumps, and so are the pieces of a truncated gaussian; the
//       jumps belong to the path-length-boundary pass (THEORY.md §3), not to this interior term.
//       The gaussian's cutoff at kGaussianCutoff sigma is a jump of W < 7e-10, likewise ignored.
//   Dual gateWeightDual(Dual len, uint layer)
//       (W(L), W'(L) dL/dθ).
//   Dual gateWeightDual(Dual len, uint layer, float centreRate)
//       the same when θ also shifts the whole gate by centreRate dθ (time calibration: W_θ(L) =
//       W(L - centreRate θ)): derivative W'(L) (dL/dθ - centreRate).
//   float gateCentreDerivative(float len, uint layer)
//       dW/dθ = -W'(L) for a shift of the gate by θ (mu, a, b or the bin start all move by θ).
#ifndef VKTG_GEOMETRY_DUAL_GLSL
#define VKTG_GEOMETRY_DUAL_GLSL
#include "lib/dual.glsl"
#include "lib/gate.glsl"

// (`length` cannot name a member: GLSL reserves it for the .length() method.)
struct DualSegment {
  Dual len;
  Dual3 dir;
};

Dual3 dBarycentric(Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv) {
  float w0 = 1.0 - uv.x - uv.y;
  return Dual3(w0 * p0.v + uv.x * p1.v + uv.y * p2.v, w0 * p0.d + uv.x * p1.d + uv.y * p2.d);
}

DualSegment dualSegment(Dual3 from, Dual3 to) {
  Dual3 delta = dSub(to, from);
  DualSegment s;
  s.len = dLength(delta);
  s.dir = dNormalize(delta);
  return s;
}

Dual3 triangleNormalDual(Dual3 p0, Dual3 p1, Dual3 p2) {
  return dNormalize(dCross(dSub(p1, p0), dSub(p2, p0)));
}

Dual triangleAreaDual(Dual3 p0, Dual3 p1, Dual3 p2) {
  return dMul(dLength(dCross(dSub(p1, p0), dSub(p2, p0))), 0.5);
}

Dual areaJacobianDual(Dual3 p0, Dual3 p1, Dual3 p2) {
  Dual3 c = dCross(dSub(p1, p0), dSub(p2, p0));
  // dA/A = (c . c') / |c|^2: the factor 1/2 and one square root cancel.
  return Dual(1.0, dot(c.v, c.d) / dot(c.v, c.v));
}

// Derivation. Let X(θ) = Σ b_i V_i(θ) be the material point with the hit's barycentrics b (fixed),
// n(θ) any normal of the moving triangle's plane, and x(θ) = o + t(θ) w the ray's hit. x lies in
// the plane through X: n(θ) . (x(θ) - X(θ)) = 0 for every θ. Differentiating,
//   n' . (x - X) + n . (t' w - X') = 0.
// At θ0 the ray hits the triangle at b, so x = X and the first term vanishes whatever n' is:
//   t' = (n . X') / (n . w),   x' = t' w,
// with n the normal at θ0 (any length: the ratio does not depend on it). The value is the exact
// surface point X(θ0), as path.glsl's surfacePoint computes it. Infinite for a ray grazing the
// plane (n . w = 0), where the hit does not move smoothly.
float rayHitRate(vec3 dir, Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv, out vec3 position) {
  Dual3 x = dBarycentric(p0, p1, p2, uv);
  vec3 n = cross(p1.v - p0.v, p2.v - p0.v);
  position = x.v;
  return dot(n, x.d) / dot(n, dir);
}

Dual3 rayHitDual(vec3 dir, Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv) {
  vec3 position;
  float rate = rayHitRate(dir, p0, p1, p2, uv, position);
  return Dual3(position, rate * dir);
}

Dual rayHitDistanceDual(vec3 origin, vec3 dir, Dual3 p0, Dual3 p1, Dual3 p2, vec2 uv) {
  vec3 position;
  float rate = rayHitRate(dir, p0, p1, p2, uv, position);
  return Dual(distance(origin, position), rate);
}

Dual dAbsCos(Dual3 n, Dual3 w) { return dAbs(dDot(n, w)); }

float gateWeightSlope(float len, uint layer) {
  if (kSpecGateTypeValue == kGateGaussian) {
    float d = len - gateNumbers().x;
    if (abs(d) > kGaussianCutoff * gateNumbers().y) return 0.0;
    float z = d / gateNumbers().y;
    return -z / gateNumbers().y * exp(-0.5 * z * z) * gateSupportNumbers().w;
  }
  if (kSpecGateTypeValue == kGateTruncatedGaussian) {
    if (len < gateNumbers().z || len > gateNumbers().w) return 0.0;
    float z = (len - gateNumbers().x) / gateNumbers().y;
    return -z / gateNumbers().y * exp(-0.5 * z * z);
  }
  return 0.0;
}

Dual gateWeightDual(Dual len, uint layer) {
  return Dual(gateWeight(len.v, layer), gateWeightSlope(len.v, layer) * len.d);
}

Dual gateWeightDual(Dual len, uint layer, float centreRate) {
  return Dual(gateWeight(len.v, layer), gateWeightSlope(len.v, layer) * (len.d - centreRate));
}

float gateCentreDerivative(float len, uint layer) { return -gateWeightSlope(len, layer); }
#endif
