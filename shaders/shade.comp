#version 460
#extension GL_GOOGLE_include_directive : require
// vktg-variant: shade_d VKTG_DERIVATIVE=1
// vktg-variant: shade_adj VKTG_ADJOINT=1
// Pass shade (shade_d: the same with K derivative lanes, kSpecLanes; shade_adj: the adjoint form,
// which records the vertex on the tape and weights emission by the adjoint image instead of
// adding it to the path, or as well with kAdjointImage): one path vertex per queued ray. Adds
// emission of hit emitters (MIS-weighted), ends paths whose length passed the gate's support,
// queues next-event estimation (standard or ellipsoidal), samples the BSDF, applies Russian
// roulette where the gate allows, and queues the continuing path for the next depth.
// Reads: ray queue (parity push.args.z & 1), hits[], paths[], scene. Writes: paths[], pathAccum,
// shadow queue, the other ray queue, statistics counters. Dispatch: indirect (ray queue size).
// One path per invocation: its connections are queued once, at the end (lib/path.glsl).
#define VKTG_DEFERRED_SHADOW_QUEUE 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/nee.glsl"
#ifdef VKTG_ADJOINT
#include "lib/adjoint.glsl"
#endif

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void shadeHit() {
  uint parity = push.args.z & 1u;
  uint index = gl_GlobalInvocationID.x;
  if (index >= counters[kCounterRays0 + parity]) return;
  uint batch = frame.pathInfo.w;
  uint path = rayQueues[parity * batch + index];
  PathState ps = loadPath(path);
  HitRecord hit = loadHit(path);
  if (hit.tuvTriangle.x < 0.0) return;  // escaped: no environment light

  setViewOfPath(ps);
  uint pixel = ps.ids.x, sampleIndex = ps.ids.y;
  uint depth = ps.ids.z + 1u;
  SurfacePoint sp = surfacePoint(floatBitsToUint(hit.tuvTriangle.w), hit.tuvTriangle.yz);
  vec3 wi = -ps.direction.xyz;
  float len = ps.position.w, comp = ps.direction.w;
  addLength(len, comp, distance(ps.position.xyz, sp.position) * ps.misc.y);
  float throughput = ps.normal.w;

  GpuShape shape = shapes[sp.shape];
  uint triangle = floatBitsToUint(hit.tuvTriangle.w);
  vec2 uv = hit.tuvTriangle.yz;
#ifdef VKTG_DERIVATIVE
  // Step the derivative state to this vertex: its position, the path length, and the factor
  // f(x_{k-2}, x_{k-1}, x_k) G(x_{k-1}, x_k) J_k the BSDF sample at x_{k-1} left pending (its value
  // is already in the throughput; the sample's density is a constant). The first hit behind a
  // pinhole stays on its camera ray (its pixel is fixed); after a point sensor it is in material
  // form like every other vertex, with the sensor's importance (constant) in place of f, as in
  // the ellipsoidal connections from the sensor, so every term shares one parametrisation.
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    uint slot = path * kSpecLanesValue + lane;
    PathDerivative pd = pathDerivs[slot];
    Dual3 previous = dual3(ps.position.xyz, pd.positionThroughput.xyz);
    bool rayForm = depth == 1u && kSpecCameraTypeValue == kCameraPerspective;
    VertexDual x = rayForm ? rayVertexDual(triangle, uv, ps.direction.xyz, lane) : surfaceVertexDual(triangle, uv, lane);
    DualSegment seg = dualSegment(previous, x.position);
    float dThroughput = pd.positionThroughput.w;
    if (!rayForm) {
      Dual3 previousNormal;
      Dual f;
      if (depth == 1u) {
        previousNormal = dual3(cameraForward());
        f = dual(1.0);
      } else {
        uint previousTriangle = floatBitsToUint(ps.previous.w);
        Dual3 p0, p1, p2;
        triangleDual(previousTriangle, lane, p0, p1, p2);
        previousNormal = triangleNormalDual(p0, p1, p2);
        Dual3 beforePrevious = dual3(ps.previous.xyz, pd.previousLength.xyz);
        Dual3 wi = dualSegment(previous, beforePrevious).dir;
        uint previousShape = floatBitsToUint(loadTriangle(previousTriangle).p0.w);
        f = bsdfOfMaterialDual(shapes[previousShape].material, previousNormal, wi, seg.dir, lane);
      }
      float dLog = dLogOf(f) + dLogOf(dAbsCos(previousNormal, seg.dir)) + dLogOf(dAbsCos(x.normal, seg.dir)) -
                   2.0 * dLogOf(seg.len) + dLogOf(x.jacobian);
      dThroughput += throughput * dLog;
    }
    pd.positionThroughput = vec4(x.position.d, dThroughput);
    pd.previousLength = vec4(previous.d, pd.previousLength.w + seg.len.d * ps.misc.y);
    pathDerivs[slot] = pd;
  }
#endif
  uint firstEllipsoid = pathFirstEllipsoidVertex(ps);
#ifdef VKTG_ADJOINT
  // The tape: this vertex, and the adjoint weights of what closes here (emission below; the
  // connections queued below add theirs in trace_shadow_rays).
  vec2 emissionWeights = vec2(0.0);
#endif
  if (kSpecTermValue != kTermPathLength && shape.emission > 0.0 && dot(sp.normal, wi) > 0.0 &&
      emitterHitCounts(depth, firstEllipsoid) && (ps.ids.w & kPathFlagNoArrivalEmission) == 0u) {
    // MIS against the standard NEE of the previous vertex, when that vertex did one (the
    // pinhole never does; the point sensor does). A hit an edge pass placed at the end of its
    // boundary segment is the only way its paths reach this emitter: no MIS.
    uint previous = depth - 1u;
    bool edgeArrival = (ps.ids.w & kPathFlagEdgeArrival) != 0u;
    bool previousDidNee = !edgeArrival && (previous > 0u || kSpecCameraTypeValue == kCameraPointSensor) &&
                          standardNeeAt(previous, firstEllipsoid);
    float mis = 1.0;
    if (previousDidNee) {
      float dist = distance(ps.position.xyz, sp.position);
      float pdfLight = areaLightPdf(shape.emission) * dist * dist / dot(sp.normal, wi);
      mis = powerHeuristic(ps.misc.x, pdfLight);
    }
    float value = throughput * shape.emission * mis;
#ifdef VKTG_ADJOINT
    emissionWeights = adjointGateWeights(pixel, len) * value;
    scatterGate(-emissionWeights.y);
    scatterEmission(sp.shape, emissionWeights.x / shape.emission);
    if ((kSpecAdjointTargetsValue & kAdjointImage) != 0u) addContribution(path, value, len);
#else
    addContribution(path, value, len);
#endif
#ifdef VKTG_DERIVATIVE
    for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
      PathDerivative pd = pathDerivs[path * kSpecLanesValue + lane];
      float dLog = pd.positionThroughput.w / throughput + laneRate(lane, kLaneEmission, sp.shape) / shape.emission;
      addContributionDerivative(path, lane, value, value * dLog, len, pd.previousLength.w);
    }
#endif
  }

#ifdef VKTG_ADJOINT
  tape[tapeIndex(depth, path)] = TapeVertex(vec4(uintBitsToFloat(triangle), uv, ps.misc.y), vec4(emissionWeights, 0.0, 0.0));
  tape[tapeIndex(0u, path)].adjoint.z = uintBitsToFloat(depth);
#endif
  // Nothing can reach the gate any more: every extension only makes the path longer.
  if (len > gateSupportNumbers().y) {
    atomicAdd(counters[kCounterEndedByGate], 1u);
    return;
  }

  NeeVertex v;
  v.position = sp.position;
  v.normal = sp.normal;
  v.wi = wi;
  v.material = materials[shape.material];
  v.isSensor = false;
  v.throughput = throughput;
  v.len = len;
  v.previousPosition = ps.position.xyz;
  v.previousLen = ps.position.w;
  v.arrivalPdf = ps.misc.x;
  v.triangle = triangle;
  v.path = path;
  v.uv = uv;
  v.materialIndex = shape.material;
  v.rayForm = depth == 1u && kSpecCameraTypeValue == kCameraPerspective;
  v.arrivalDir = ps.direction.xyz;
  v.firstEllipsoidVertex = firstEllipsoid;
  neeAtVertex(path, v, depth, pixel, sampleIndex);

  // gateInfo.w (max depth) is the most segments a path may have: NEE here made depth + 1.
  if (depth >= frame.gateInfo.w) {
    atomicAdd(counters[kCounterEndedByDepth], 1u);
    return;
  }
  Rng rb = rngForBounce(viewPixel(pixel), sampleIndex, depth, kRngSlotBsdf, viewSeed());
  BsdfSample bs;
  if (!bsdfSample(v.material, sp.normal, wi, rngNext4(rb).xyz, bs)) return;
  throughput *= bs.weight;
  if (!(throughput > 0.0)) return;

  // Russian roulette only once the path has reached the gate's support: before that the path
  // has contributed nothing yet, and its length (not a bounce count) already bounds it.
  if (depth >= frame.pathInfo.x && len >= gateSupportNumbers().x) {
    Rng rr = rngForBounce(viewPixel(pixel), sampleIndex, depth, kRngSlotLight, viewSeed());
    float survive = clamp(throughput, 0.05, 0.95);
    if (rngNext4(rr).w >= survive) {
      atomicAdd(counters[kCounterEndedByRoulette], 1u);
      return;
    }
    throughput /= survive;
  }
#ifdef VKTG_DERIVATIVE
  // The new segment's factor stays pending until the next vertex is known; its value (the
  // sample weight) scales what is already differentiated.
  float scale = throughput / ps.normal.w;
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) pathDerivs[path * kSpecLanesValue + lane].positionThroughput.w *= scale;
#endif

  float ior = ps.misc.y;
  if (bs.transmitted) ior = dot(sp.normal, bs.wo) < 0.0 ? v.material.ior : 1.0;
  ps.previous = vec4(ps.position.xyz, hit.tuvTriangle.w);
  ps.position = vec4(sp.position, len);
  ps.direction = vec4(bs.wo, comp);
  ps.normal = vec4(sp.normal, throughput);
  ps.misc = vec4(bs.pdf, ior, viewBits(), 0.0);
  ps.ids.z = depth;
  ps.ids.w &= ~(kPathFlagEdgeArrival | kPathFlagNoArrivalEmission);
  paths[path] = ps;
  uint slot = atomicAdd(counters[kCounterRays0 + (parity ^ 1u)], 1u);
  rayQueues[(parity ^ 1u) * batch + slot] = path;
}

void main() {
  shadeHit();
  flushShadowQueue();
#ifdef VKTG_ADJOINT
  countScatterFaults();
#endif
}
