#version 460
#extension GL_GOOGLE_include_directive : require
// vktg-variant: connect_camera_boundary_adj VKTG_ADJOINT=1
// Pass connect_camera_boundary: the path-length-boundary term (THEORY.md §3) of the paths whose
// only free vertex the per-pixel pass cannot place on a jump. That pass starts its ellipsoidal
// connections at the first hit behind a pinhole (the pixel fixes it) and at the sensor itself at a
// point sensor, so it misses
//   two segments behind a pinhole, camera -> x1 -> light: an ellipsoidal connection with the
//     pinhole and a light sample as foci puts x1 exactly on L = s_j;
//   one segment, camera -> y on an emitter seen directly (any camera): y on the sphere L = |y - c|
//     = s_j, sampled as the ellipsoid with both foci at the camera;
// and the pixel follows from the direction the camera sees the vertex in (light-tracing style,
// splatted by accumulate_splats). Each sample picks one of the two (kDirectProbability when both
// can occur).
//
// The interior pass differentiates these paths with the first hit on its fixed camera ray behind a
// pinhole (a material point at a point sensor), so dL/dθ is taken in that parametrisation too: the
// boundary term is ΔW(s_j) ∫ δ(L - s_j) (∂L/∂θ)|ray F du, and changing variables from the image
// plane u to the vertex's area (F du = W_e G(c, x) ... dA(x)) lets the ellipsoid sampler's co-area
// weight handle δ(L - s_j).
//
// One sample per invocation, two path slots (2i, 2i + 1: one per jump of an antithetic pair, whose
// connections may land in different pixels). Each connection queues a shadow ray with its value
// and dL/dθ per lane; trace_shadow_rays_d adds ΔW(s_j) value (dL/dθ - rate of the gate centre) to
// the slot's lanes when every segment is unoccluded.
// Reads: scene, BVH, camera, lights, velocities. Writes: paths[2i, 2i + 1] (pixel), shadow queue,
// shadowDerivs. Dispatch: ceil(samples of the batch / kWorkgroupSize); push.args: x first sample of
// the batch, w samples in the batch.
// _adj, the adjoint form: each connection records its vertices (ShadowAdjoint) instead of lanes, and
// trace_shadow_rays_adj scatters ΔW(s_j) a f dL/dθ from them.
#ifndef VKTG_ADJOINT
#define VKTG_DERIVATIVE 1
#endif
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/nee.glsl"
#include "lib/camera.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

// Share of the samples that look for directly seen emitters when two-segment paths exist too.
const float kDirectProbability = 0.25;

// The connection c -> x1 -> y of total length s into slot `slot`.
void connect(uint slot, vec3 c, LightSample ls, float s, uint jump, float weight, vec4 uEllipsoid, float line) {
  atomicAdd(counters[kCounterEllipsoidQueries], 1u);
  EllipsoidSample es;
  if (!sampleEllipsoidConnectionStratified(c, ls.position, s, uEllipsoid, line, es)) {
    atomicAdd(counters[kCounterEllipsoidEmpty], 1u);
    return;
  }
  SurfacePoint x1 = surfacePoint(es.triangle, es.barycentrics);
  vec3 d1 = x1.position - c, d2 = ls.position - x1.position;
  float len1 = length(d1), len2 = length(d2);
  if (!(len1 > 0.0) || !(len2 > 0.0)) return;
  vec3 w1 = d1 / len1, w2 = d2 / len2;
  uint pixel;
  float importance = cameraImportance(w1, pixel);
  if (importance == 0.0) return;
  float f = bsdfEval(materials[shapes[x1.shape].material], x1.normal, -w1, w2);
  if (f == 0.0) return;
  float g = abs(dot(x1.normal, w1)) / (len1 * len1) * abs(dot(x1.normal, w2)) / (len2 * len2);
  if (!ls.isPoint) {
    float cosY = dot(ls.normal, -w2);
    if (cosY <= 0.0) return;
    g *= cosY;
  }
  float value = importance * f * g * ls.emission * es.weight * weight / ls.pdf;
  uint queued = queueShadowRay(slot, kNoTape, kConnectionStandard, c, x1.position, ls.position, 2u, value, s, jump);
  if (queued == 0xffffffffu) return;
  paths[slot].ids.x = pixel;
#ifdef VKTG_ADJOINT
  // x1 stays on its camera ray (this connection exists behind a pinhole only).
  shadowAdjoint[queued] = ShadowAdjoint(uvec4(es.triangle, floatBitsToUint(es.barycentrics), 1u),
                                        uvec4(ls.index, floatBitsToUint(ls.barycentrics), 0u));
#else
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    Dual3 x = firstHitPositionDual(es.triangle, es.barycentrics, w1, lane);
    LightDual y = lightDual(ls, lane);
    float dLen = dualSegment(dual3(c), x).len.d + dualSegment(x, y.position).len.d;
    storeShadowDerivative(queued, lane, 0.0, dLen);
  }
#endif
}

// The path c -> y of length s, y on an emitter, into slot `slot`. The ellipsoid with both foci at c
// and total length 2s is the sphere |y - c| = s; its co-area weight is for δ(2 (|y - c| - s)) =
// δ(|y - c| - s) / 2, hence the factor 2.
void connectDirect(uint slot, vec3 c, float s, uint jump, float weight, vec4 uEllipsoid, float line) {
  atomicAdd(counters[kCounterEllipsoidQueries], 1u);
  EllipsoidSample es;
  if (!sampleEllipsoidConnectionStratified(c, c, 2.0 * s, uEllipsoid, line, es)) {
    atomicAdd(counters[kCounterEllipsoidEmpty], 1u);
    return;
  }
  SurfacePoint y = surfacePoint(es.triangle, es.barycentrics);
  float emission = shapes[y.shape].emission;
  if (!(emission > 0.0)) return;
  vec3 d = y.position - c;
  float r = length(d);
  if (!(r > 0.0)) return;
  vec3 w = d / r;
  float cosY = dot(y.normal, -w);
  if (cosY <= 0.0) return;  // area lights emit from their front face
  uint pixel;
  float importance = cameraImportance(w, pixel);
  if (importance == 0.0) return;
  float value = importance * emission * cosY / (r * r) * 2.0 * es.weight * weight;
  uint queued = queueShadowRay(slot, kNoTape, kConnectionStandard, c, y.position, vec3(0.0), 1u, value, s, jump);
  if (queued == 0xffffffffu) return;
  paths[slot].ids.x = pixel;
#ifdef VKTG_ADJOINT
  // y as the interior pass sees it: on its camera ray behind a pinhole, a material point at a sensor.
  uint rayForm = kSpecCameraTypeValue == kCameraPerspective ? 1u : 0u;
  shadowAdjoint[queued] = ShadowAdjoint(uvec4(es.triangle, floatBitsToUint(es.barycentrics), rayForm), uvec4(0xffffffffu));
#else
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane)
    storeShadowDerivative(queued, lane, 0.0, dualSegment(dual3(c), firstHitPositionDual(es.triangle, es.barycentrics, w, lane)).len.d);
#endif
}

// gateBoundaryJumps with the line's number picking the jump where it has one (then rescaled to be
// uniform again given the jump), `uJump` otherwise.
uint jumpsAlongLine(float reach, float uJump, inout LineDraw line, out uint first, out float weight) {
  uint n = gateBoundaryJumps(reach, line.u >= 0.0 ? line.u : uJump, first, weight);
  // weight: how many jumps it chose among, each taking an equal share of [0, 1)
  if (n == 1u && line.u >= 0.0) narrowLine(min(floor(line.u * weight), weight - 1.0) / weight, 1.0 / weight, line);
  return n;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  // Random numbers are keyed by the sample's index within its view.
  setViewOfSample(push.args.x + i);
  uint sampleIndex = viewSample(push.args.x + i);
  for (uint side = 0u; side < 2u; ++side) {
    paths[2u * i + side].ids = uvec4(kNoPixel, sampleIndex, 0u, 0u);
    paths[2u * i + side].misc.z = viewBits();
  }
  uint seed = viewSeed();
  Rng rg = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotGate, seed);
  Rng rl = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotEllipsoidLight, seed);
  Rng re = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotEllipsoid, seed);
  vec3 c = cameraPosition();
  vec4 uGate = rngNext4(rg), uEllipsoid = rngNext4(re);
  // The samples of a view share the sensor, and at a point light the light too, so their
  // ellipsoids are one per jump: one stratified number per sample makes each choice in turn (the
  // kind of path, the jump, then the point on the curve the jump's ellipsoid cuts from the scene),
  // which spreads the samples evenly over all of them (docs/theory.md 3.7).
  LineDraw line = noLineDraw();
  const uint lineDimension = kRngDimBounceBase + kRngSlotEllipsoid;
  if (kSpecStratifiedBoundaryValue != 0u) line.u = stratifiedUnit(sampleIndex, lineDimension, seed);
  bool twoSegments = kSpecCameraTypeValue == kCameraPerspective && frame.gateInfo.w >= 2u;
  bool direct = sceneHasLightType(kLightAreaTriangle);
  float pDirect = direct ? (twoSegments ? kDirectProbability : 1.0) : 0.0;
  uint first;
  float weight;
  if (decideAlongLine(pDirect, 1.0, uGate.y, line)) {
    uint n = jumpsAlongLine(0.0, uGate.x, line, first, weight);
    for (uint k = 0u; k < n; ++k)
      connectDirect(2u * i + k, c, gateJumpLocation(first + k), first + k, weight / pDirect, uEllipsoid, line.u);
    return;
  }
  if (!twoSegments) return;  // at a point sensor the per-pixel pass places two-segment paths
  LightSample ls;
  if (!sampleLight(rngNext4(rl).xyz, ls)) return;
  uint n = jumpsAlongLine(distance(c, ls.position), uGate.x, line, first, weight);
  for (uint k = 0u; k < n; ++k)
    connect(2u * i + k, c, ls, gateJumpLocation(first + k), first + k, weight / (1.0 - pDirect), uEllipsoid, line.u);
}
