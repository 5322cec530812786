#version 460
#extension GL_GOOGLE_include_directive : require
// Pass connect_camera_boundary (path-length-boundary term, THEORY.md §3, of the paths camera ->
// x1 -> light behind a pinhole): the per-pixel pass starts its ellipsoidal connections at the
// first hit, which the pixel fixes, so these two-segment paths have no vertex it can place on a
// jump. Here x1 is that vertex: an ellipsoidal connection with the pinhole and a light sample as
// foci puts the path exactly on L = s_j, and the pixel follows from x1's direction (light-tracing
// style, splatted by accumulate_splats).
//
// The interior pass differentiates these paths with x1 on its fixed camera ray, so dL/dθ is taken
// in that parametrisation too (x1's velocity along the ray through it): the boundary term is
//   ΔW(s_j) ∫ δ(L - s_j) (∂L/∂θ)|ray F du,
// and changing variables from the image plane u to x1's area (F du = W_e G(c, x1) f G(x1, y) L_e
// dA(x1)) lets the ellipsoid sampler's co-area weight handle δ(L - s_j).
//
// One sample per invocation, two path slots (2i, 2i + 1: one per jump of an antithetic pair, whose
// connections may land in different pixels). Each connection queues a two-segment shadow ray with
// its value W_e G f G L_e weight / p and dL/dθ per lane; trace_shadow_rays_d adds ΔW(s_j) value
// (dL/dθ - rate of the gate centre) to the slot's lanes when both segments are unoccluded.
// Reads: scene, BVH, camera, lights, velocities. Writes: paths[2i, 2i + 1] (pixel), shadow queue,
// shadowDerivs. Dispatch: ceil(samples of the batch / kWorkgroupSize); push.args: x first sample of
// the batch, w samples in the batch.
#define VKTG_DERIVATIVE 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/nee.glsl"
#include "lib/camera.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

// The connection c -> x1 -> y of total length s into slot `slot`.
void connect(uint slot, vec3 c, LightSample ls, float s, uint jump, float weight, vec4 uEllipsoid) {
  atomicAdd(counters[kCounterEllipsoidQueries], 1u);
  EllipsoidSample es;
  if (!sampleEllipsoidConnection(c, ls.position, s, uEllipsoid, es)) {
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
  uint queued = queueShadowRay(slot, c, x1.position, ls.position, 2u, value, s, jump);
  if (queued == 0xffffffffu) return;
  paths[slot].ids.x = pixel;
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    VertexDual x = rayVertexDual(es.triangle, es.barycentrics, w1, lane);
    LightDual y = lightDual(ls, lane);
    float dLen = dualSegment(dual3(c), x.position).len.d + dualSegment(x.position, y.position).len.d;
    storeShadowDerivative(queued, lane, 0.0, dLen);
  }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  uint sampleIndex = push.args.x + i;
  for (uint side = 0u; side < 2u; ++side) paths[2u * i + side].ids = uvec4(kNoPixel, sampleIndex, 0u, 0u);
  uint seed = frame.image.w;
  Rng rg = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotGate, seed);
  Rng rl = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotEllipsoidLight, seed);
  Rng re = rngForBounce(kNoPixel, sampleIndex, 0u, kRngSlotEllipsoid, seed);
  LightSample ls;
  if (!sampleLight(rngNext4(rl).xyz, ls)) return;
  vec3 c = frame.cameraPosition.xyz;
  uint first;
  float weight;
  uint n = gateBoundaryJumps(distance(c, ls.position), rngNext4(rg).x, first, weight);
  vec4 uEllipsoid = rngNext4(re);
  for (uint k = 0u; k < n; ++k)
    connect(2u * i + k, c, ls, gateJumpLocation(first + k), first + k, weight, uEllipsoid);
}
