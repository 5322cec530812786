// Forward-mode derivatives of path contributions (THEORY.md §2-3, interior term), one lane at a
// time: lane k differentiates with respect to parameter θ_k (lanes[k]). Vertices are in material
// form (a point of a triangle moves with the triangle's vertex velocities) except the first hit,
// which stays on its fixed camera ray (ray form; primary silhouettes belong to the edge pass).
// Sampling densities are detached: they are constants of the sample, not of θ.
// Requires VKTG_DERIVATIVE, lib/common.glsl, lib/bindings.glsl, lib/nee.glsl first.
#ifndef VKTG_PATH_DERIVATIVE_GLSL
#define VKTG_PATH_DERIVATIVE_GLSL
#include "lib/bsdf_dual.glsl"
#include "lib/geometry_dual.glsl"
#include "lib/lights.glsl"
#include "lib/path.glsl"

uint vertexCount() { return floatBitsToUint(frame.sceneInfo.w); }

// The triangle's vertices with their velocities for `lane`.
void triangleDual(uint triangle, uint lane, out Dual3 p0, out Dual3 p1, out Dual3 p2) {
  GpuTriangle t = loadTriangle(triangle);
  uvec4 ids = triangleVerts[triangle];
  uint base = lane * vertexCount();
  p0 = dual3(t.p0.xyz, vertexVelocity[base + ids.x].xyz);
  p1 = dual3(t.p1.xyz, vertexVelocity[base + ids.y].xyz);
  p2 = dual3(t.p2.xyz, vertexVelocity[base + ids.z].xyz);
}

// A surface vertex of the path for one lane: position, unit normal, area Jacobian.
struct VertexDual {
  Dual3 position;
  Dual3 normal;
  Dual jacobian;
};

VertexDual surfaceVertexDual(uint triangle, vec2 uv, uint lane) {
  Dual3 p0, p1, p2;
  triangleDual(triangle, lane, p0, p1, p2);
  VertexDual v;
  v.position = dBarycentric(p0, p1, p2, uv);
  v.normal = triangleNormalDual(p0, p1, p2);
  v.jacobian = areaJacobianDual(p0, p1, p2);
  return v;
}

// The first hit, kept on its fixed ray (no area Jacobian: it is measured in ray directions).
VertexDual rayVertexDual(uint triangle, vec2 uv, vec3 dir, uint lane) {
  Dual3 p0, p1, p2;
  triangleDual(triangle, lane, p0, p1, p2);
  VertexDual v;
  v.position = rayHitDual(dir, p0, p1, p2, uv);
  v.normal = triangleNormalDual(p0, p1, p2);
  v.jacobian = dual(1.0);
  return v;
}

// Position of a camera ray's first hit along `dir` for one lane, in the interior pass's
// parametrisation: on its fixed ray behind a pinhole, a material point at a point sensor.
Dual3 firstHitPositionDual(uint triangle, vec2 uv, vec3 dir, uint lane) {
  Dual3 p0, p1, p2;
  triangleDual(triangle, lane, p0, p1, p2);
  if (kSpecCameraTypeValue == kCameraPerspective) return rayHitDual(dir, p0, p1, p2, uv);
  return dBarycentric(p0, p1, p2, uv);
}

float laneRate(uint lane, uint kind, uint target) {
  GpuLane l = lanes[lane];
  return (l.info.x == kind && l.info.y == target) ? 1.0 : 0.0;
}

Dual materialAlbedo(GpuMaterial m, uint material, uint lane) { return dual(m.albedo, laneRate(lane, kLaneAlbedo, material)); }
Dual materialRoughness(GpuMaterial m, uint material, uint lane) { return dual(m.roughness, laneRate(lane, kLaneRoughness, material)); }
Dual materialIor(GpuMaterial m, uint material, uint lane) { return dual(m.ior, laneRate(lane, kLaneIor, material)); }

// f of `material` between unit directions wi and wo about `normal`.
Dual bsdfOfMaterialDual(uint material, Dual3 normal, Dual3 wi, Dual3 wo, uint lane) {
  GpuMaterial m = materials[material];
  return bsdfEvalDual(m, materialAlbedo(m, material, lane), materialRoughness(m, material, lane),
                      materialIor(m, material, lane), normal, wi, wo);
}

// The light point of a connection for one lane: position, normal, Jacobian, emission.
struct LightDual {
  Dual3 position;
  Dual3 normal;
  Dual jacobian;
  Dual emission;
};

LightDual lightDual(LightSample ls, uint lane) {
  LightDual l;
  if (ls.isPoint) {
    GpuLane info = lanes[lane];
    bool moves = info.info.x == kLaneGeometry && info.info.z == 1u && info.info.y == ls.index;
    l.position = dual3(ls.position, moves ? info.lightVelocity.xyz : vec3(0.0));
    l.normal = dual3(vec3(0.0));
    l.jacobian = dual(1.0);
    l.emission = dual(ls.emission, laneRate(lane, kLaneIntensity, ls.index));
    return l;
  }
  VertexDual v = surfaceVertexDual(ls.triangle, ls.barycentrics, lane);
  l.position = v.position;
  l.normal = v.normal;
  l.jacobian = v.jacobian;
  uint shape = floatBitsToUint(loadTriangle(ls.triangle).p0.w);
  l.emission = dual(ls.emission, laneRate(lane, kLaneEmission, shape));
  return l;
}

// Relative derivative d(log x) of a positive dual; 0 where x vanishes (no contribution there).
float dLogOf(Dual x) { return x.v != 0.0 ? x.d / x.v : 0.0; }

// Derivative lanes of a deferred contribution: (d value, d path length) for its shadow ray.
void storeShadowDerivative(uint slot, uint lane, float dValue, float dLen) {
  if (slot == 0xffffffffu) return;
  shadowDerivs[slot * kSpecLanesValue + lane] = vec2(dValue, dLen);
}

// Adds the derivative of W(L) * value to lane `lane` of the path's accumulator:
// W dvalue + W'(L) (dL - rate_centre) value, rate_centre = 1 for the gate-centre lane.
void addContributionDerivative(uint path, uint lane, float value, float dValue, float len, float dLen) {
  if (isnan(dValue) || isinf(dValue) || isnan(dLen) || isinf(dLen)) {
    atomicAdd(counters[kCounterNonFinite], 1u);
    return;
  }
  uint first, count;
  gateLayers(len, first, count);
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
  float centreRate = lanes[lane].info.x == kLaneGateCenter ? 1.0 : 0.0;
  for (uint k = first; k < first + count; ++k) {
    Dual w = gateWeightDual(dual(len, dLen), k, centreRate);
    float d = w.v * dValue + w.d * value;
    if (d != 0.0) pathAccum[(path * layers + k) * channels + 1u + lane] += d;
  }
}
#endif
