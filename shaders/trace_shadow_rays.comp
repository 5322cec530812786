#version 460
#extension GL_GOOGLE_include_directive : require
// vktg-variant: trace_shadow_rays_d VKTG_DERIVATIVE=1
// Pass trace_shadow_rays (_d: also adds the connection's derivative lanes): visibility of every
// queued connection (one or two segments); adds the value of the unoccluded ones to their path's
// accumulator at the connection's path length. One invocation per path on the shadow queue, which
// visits the path's filled slots in order and clears its slot mask for the next bounce.
// Reads: shadow queue, slot masks, scene BVH. Writes: pathAccum, slot masks. Dispatch: indirect
// (paths on the shadow queue).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/bvh.glsl"
#include "lib/path.glsl"
#ifdef VKTG_DERIVATIVE
#include "lib/path_derivative.glsl"
#endif

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

bool segmentVisible(vec3 a, vec3 b) {
  vec3 d = b - a;
  float dist = length(d);
  float eps = frame.sceneInfo.x;
  if (dist <= 2.0 * eps) return true;
  return !traceAny(a, d / dist, eps, dist - eps);
}

// One connection: its contribution if every segment is unoccluded.
void traceConnection(uint slot) {
  ShadowRay r = shadowRays[slot];
  if (!segmentVisible(r.p0Value.xyz, r.p1Length.xyz)) return;
  if (r.info.y == 2u && !segmentVisible(r.p1Length.xyz, r.p2.xyz)) return;
#ifdef VKTG_DERIVATIVE
  if (kSpecTermValue == kTermPathLength) {
    // ΔW_k(s) f dL/dθ for the layers whose weight jumps at s (gate-centre lane: the jump moves
    // with θ, so dL/dθ - 1).
    uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
    uint jump = r.info.z;
    uint firstLayer = kSpecGateTypeValue == kGateBins ? (jump > 0u ? jump - 1u : 0u) : 0u;
    uint lastLayer = kSpecGateTypeValue == kGateBins ? min(jump, layers - 1u) : 0u;
    for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
      float dLen = shadowDerivs[slot * kSpecLanesValue + lane].y;
      float rate = dLen - (lanes[lane].info.x == kLaneGateCenter ? 1.0 : 0.0);
      for (uint k = firstLayer; k <= lastLayer; ++k) {
        float d = gateJumpSize(jump, k) * r.p0Value.w * rate;
        if (isnan(d) || isinf(d)) atomicAdd(counters[kCounterNonFinite], 1u);
        else if (d != 0.0) pathAccum[(r.info.x * layers + k) * channels + 1u + lane] += d;
      }
    }
    return;
  }
#endif
  addContribution(r.info.x, r.p0Value.w, r.p1Length.w);
#ifdef VKTG_DERIVATIVE
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    vec2 d = shadowDerivs[slot * kSpecLanesValue + lane];
    addContributionDerivative(r.info.x, lane, r.p0Value.w, d.x, r.p1Length.w, d.y);
  }
#endif
}

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= counters[kCounterShadow]) return;
  uint batch = frame.pathInfo.w;
  uint path = rayQueues[2u * batch + index];
  uint mask = rayQueues[3u * batch + path];
  rayQueues[3u * batch + path] = 0u;
  atomicAdd(counters[kCounterShadowRays], uint(bitCount(mask)));
  // In slot order: the path's accumulator sees its contributions in the same order on every run.
  for (uint local = 0u; local < kShadowRaysPerPath; ++local)
    if ((mask & (1u << local)) != 0u) traceConnection(path * kShadowRaysPerPath + local);
}
