#version 460
#extension GL_GOOGLE_include_directive : require
// vktg-variant: trace_shadow_rays_d VKTG_DERIVATIVE=1
// vktg-variant: trace_shadow_rays_adj VKTG_ADJOINT=1
// Pass trace_shadow_rays (_d: also adds the connection's derivative lanes): visibility of every
// queued connection (one or two segments); adds the value of the unoccluded ones to their path's
// accumulator at the connection's path length. One invocation per path on the shadow queue, which
// visits the path's filled slots in order and clears its slot mask for the next bounce.
// Reads: shadow queue, slot masks, scene BVH. Writes: pathAccum, slot masks. Dispatch: indirect
// (paths on the shadow queue).
// _adj, the adjoint form: an unoccluded connection's adjoint weights (lib/adjoint.glsl) go to its
// first vertex's tape entry, for backprop_paths to carry back along the path, and the gradient of
// its own factors (the connection's segments, BSDFs, light) straight into the accumulators; with
// kAdjointImage the interior term's connections also add their value as the plain pass does.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/bvh.glsl"
#include "lib/path.glsl"
#ifdef VKTG_DERIVATIVE
#include "lib/path_derivative.glsl"
#endif
#ifdef VKTG_ADJOINT
#include "lib/nee.glsl"
#include "lib/adjoint.glsl"
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

#ifdef VKTG_ADJOINT
// The light end of a connection, as sampleLight produced it.
struct LightEnd {
  vec3 position, normal;
  float emission;
  bool isPoint;
  uint triangle, shape;
  vec2 uv;
};

LightEnd lightEnd(uvec4 record) {
  LightEnd l;
  GpuLight light = lights[record.x];
  l.isPoint = sceneHasLightType(kLightPoint) && light.type == kLightPoint;
  l.uv = uintBitsToFloat(record.yz);
  if (l.isPoint || !sceneHasLightType(kLightAreaTriangle)) {
    l.position = pointLightPosition(record.x, light.positionIntensity.xyz);
    l.normal = vec3(0.0);
    l.emission = light.positionIntensity.w;
    l.triangle = 0xffffffffu;
    l.shape = 0u;
    return l;
  }
  SurfacePoint sp = surfacePoint(light.triangle, l.uv);
  l.position = sp.position;
  l.normal = sp.normal;
  l.emission = shapes[sp.shape].emission;
  l.triangle = light.triangle;
  l.shape = sp.shape;
  return l;
}

// Scatters the adjoint of a connection's light end, and the derivative of its emission.
void scatterLightEnd(LightEnd l, uint lightIndex, VertexAdjoint y, float valueWeight) {
  if (l.isPoint) {
    scatterPointLight(lightIndex, valueWeight / l.emission, y.position);
    return;
  }
  scatterEmission(l.shape, valueWeight / l.emission);
  scatterSurfaceAdjoint(l.triangle, l.uv, y, false);
}

// A connection from the camera (connect_camera_boundary): the path-length boundary of paths whose
// first hit the pixel fixes; only their length is differentiated.
void cameraConnectionAdjoint(ShadowRay r, ShadowAdjoint sa, float lengthWeight) {
  SurfacePoint m = surfacePoint(sa.middle.x, uintBitsToFloat(sa.middle.yz));
  bool rayForm = sa.middle.w != 0u;
  vec3 camera = cameraPosition();
  Segment first = Segment(camera, camera, m.position, cameraForward(), m.normal, 0u, false, false, false);
  VertexAdjoint c = noAdjoint(), x = noAdjoint(), y = noAdjoint(), unused = noAdjoint();
  segmentAdjoint(first, 0.0, lengthWeight, unused, c, x);
  if (sa.light.x != 0xffffffffu) {
    LightEnd l = lightEnd(sa.light);
    Segment second = Segment(camera, m.position, l.position, m.normal, l.normal, 0u, false, false, false);
    segmentAdjoint(second, 0.0, lengthWeight, unused, x, y);
    scatterLightEnd(l, sa.light.x, y, 0.0);
  }
  scatterSurfaceAdjoint(sa.middle.x, uintBitsToFloat(sa.middle.yz), x, rayForm);
}

// A connection from path vertex `depth`: (the value weight, the length weight) of its contribution
// go onto the tape; its own factors' gradient into the accumulators.
void pathConnectionAdjoint(ShadowRay r, ShadowAdjoint sa, uint path, float valueWeight, float lengthWeight) {
  uint depth = r.info.w;
  TapeVertex entry = tape[tapeIndex(depth, path)];
  tape[tapeIndex(depth, path)].adjoint.xy = entry.adjoint.xy + vec2(valueWeight, lengthWeight);
  TapePoint a = tapePoint(depth, path);
  TapePoint p = depth > 0u ? tapePoint(depth - 1u, path) : a;
  LightEnd l = lightEnd(sa.light);
  bool hasBsdf = depth > 0u;  // at the sensor its importance (constant) takes f's place
  // The connections this pass can hold (lib/nee.glsl's neeAtVertex): one segment a -> y from
  // standard NEE unless only the boundary term runs; two, a -> m -> y through an ellipsoidal vertex,
  // from ellipsoidal NEE or on the gate's jumps. Only those are compiled in, and both share the
  // code of the first segment (a CPU device runs both sides of a branch).
  const bool oneSegment = kSpecTermValue != kTermPathLength;
  const bool twoSegments = kSpecNeeModeValue != kNeeStandard || kSpecTermValue != kTermInterior;
  bool viaMiddle = twoSegments && !(oneSegment && sa.middle.x == 0xffffffffu);
  vec2 mUv = uintBitsToFloat(sa.middle.yz);
  SurfacePoint m = SurfacePoint(vec3(0.0), vec3(0.0), 0u);
  if (viaMiddle) m = surfacePoint(sa.middle.x, mUv);
  vec3 bPosition = viaMiddle ? m.position : l.position, bNormal = viaMiddle ? m.normal : l.normal;
  bool bIsSurface = viaMiddle || !l.isPoint;
  VertexAdjoint pBar = noAdjoint(), aBar = noAdjoint(), bBar = noAdjoint(), yBar = noAdjoint();
  Segment first = Segment(p.position, a.position, bPosition, a.normal, bNormal, a.material, hasBsdf, bIsSurface, bIsSurface);
  segmentAdjoint(first, valueWeight, lengthWeight, pBar, aBar, bBar);
  if (viaMiddle) {
    Segment second = Segment(a.position, m.position, l.position, m.normal, l.normal, shapes[m.shape].material, true,
                             !l.isPoint, !l.isPoint);
    segmentAdjoint(second, valueWeight, lengthWeight, aBar, bBar, yBar);
    scatterSurfaceAdjoint(sa.middle.x, mUv, bBar, false);
  } else {
    yBar = bBar;
  }
  scatterLightEnd(l, sa.light.x, yBar, valueWeight);
  if (depth >= 1u) scatterSurfaceAdjoint(a.triangle, a.uv, aBar, onCameraRay(depth));
  if (depth >= 2u) scatterSurfaceAdjoint(p.triangle, p.uv, pBar, onCameraRay(depth - 1u));
}
#endif

// One connection: its contribution if every segment is unoccluded.
void traceConnection(uint slot) {
  ShadowRay r = shadowRays[slot];
  if (!segmentVisible(r.p0Value.xyz, r.p1Length.xyz)) return;
  if (r.info.y == 2u && !segmentVisible(r.p1Length.xyz, r.p2.xyz)) return;
#ifdef VKTG_ADJOINT
  uint path = r.info.x;
  uint pixel = paths[path].ids.x;
  if (pixel == kNoPixel) return;
  ShadowAdjoint sa = shadowAdjoint[slot];
  // Path-length boundary (a connection on a jump): only the length moves the path across the
  // jump (gate centre: -1). A pass of one term holds connections of one kind only.
  bool onJump = kSpecTermValue == kTermPathLength || (kSpecTermValue != kTermInterior && r.info.z != kNoJump);
  if (!onJump && (kSpecAdjointTargetsValue & kAdjointImage) != 0u) addContribution(path, r.p0Value.w, r.p1Length.w);
  vec2 weights = onJump ? vec2(0.0, adjointJumpWeight(pixel, r.info.z)) : adjointGateWeights(pixel, r.p1Length.w);
  weights *= r.p0Value.w;
  if (isnan(weights.x) || isinf(weights.x) || isnan(weights.y) || isinf(weights.y)) {
    ++scatterNonFinite;  // counted as the pass ends
    return;
  }
  if (weights == vec2(0.0)) return;
  scatterGate(-weights.y);
  if (kSpecCameraConnectionsValue != 0u) cameraConnectionAdjoint(r, sa, weights.y);
  else pathConnectionAdjoint(r, sa, path, weights.x, weights.y);
  return;
#endif
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

void traceConnections() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= counters[kCounterShadow]) return;
  uint batch = frame.pathInfo.w;
  uint path = rayQueues[2u * batch + index];
  uint mask = rayQueues[3u * batch + path];
  rayQueues[3u * batch + path] = 0u;
  atomicAdd(counters[kCounterShadowRays], uint(bitCount(mask)));
  // The gate meets a connection's length as the path's view counts it (its path offset); the adjoint
  // also reads the camera and the lights as that view has them.
  setViewOfPath(paths[path]);
  // In slot order: the path's accumulator sees its contributions in the same order on every run.
  // A CPU device masks lanes rather than branching, so a loop over all slots would run a
  // connection's code, traversals included, for every empty slot: it visits the filled ones only.
  // On a GPU the fixed loop over every slot measured faster (the default room's render 10% on an
  // H100, docs/benchmarks.md); both visit the same slots in the same order.
  if (kSpecFilledSlotsOnlyValue != 0u) {
    for (uint left = mask; left != 0u; left &= left - 1u) traceConnection(shadowSlot(path, uint(findLSB(left))));
  } else {
    for (uint local = 0u; local < kShadowRaysPerPath; ++local)
      if ((mask & (1u << local)) != 0u) traceConnection(shadowSlot(path, local));
  }
}

void main() {
  traceConnections();
#ifdef VKTG_ADJOINT
  countScatterFaults();
#endif
}
