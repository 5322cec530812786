// Helpers on path state shared by the passes: compensated path length, contributions into the
// per-path accumulator (one slot per gate layer; only the invocation handling the path writes it,
// so plain adds in a fixed order), shadow-ray queueing, vertex reconstruction.
#ifndef VKTG_PATH_GLSL
#define VKTG_PATH_GLSL
#include "lib/gate.glsl"

// Kahan-compensated addition of a segment to the path length: lengths of many segments summed in
// float lose the millimetres a narrow gate resolves.
void addLength(inout float len, inout float compensation, float segment) {
  // `precise`: the compensation is algebraically zero, so a compiler free to reassociate would
  // remove it.
  precise float y = segment - compensation;
  precise float t = len + y;
  compensation = (t - len) - y;
  len = t;
}

// Adds W_k(L) * value to every layer k of the path's accumulator; non-finite values are counted
// (kCounterNonFinite, which must stay 0) instead of entering the image.
void addContribution(uint path, float value, float len) {
  if (isnan(value) || isinf(value) || isnan(len) || isinf(len)) {
    atomicAdd(counters[kCounterNonFinite], 1u);
    return;
  }
  if (value == 0.0) return;
  uint first, count;
  gateLayers(len, first, count);
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
  for (uint k = first; k < first + count; ++k) {
    float w = gateWeight(len, k);
    if (w != 0.0) pathAccum[(path * layers + k) * channels] += w * value;
  }
}

// Where connection slot `local` of `path` lives: slot-major, so that the paths of a pass, which
// fill the same slot, write and read neighbouring records.
uint shadowSlot(uint path, uint local) { return local * frame.pathInfo.w + path; }

#ifdef VKTG_DEFERRED_SHADOW_QUEUE
// A pass whose invocation holds one path and all of its connections in this bounce (shade) keeps
// the slots it fills here and queues the path once, in flushShadowQueue, instead of an atomic OR
// into device memory per connection (on an H100 the default room rendered 9% faster).
uint deferredShadowPath = 0u;
uint deferredShadowMask = 0u;
#endif

// Queues a connection from the path's vertex `depth` (kNoTape: the camera) into its fixed slot
// (kConnection* `kind`, shared.h); returns the slot (~0 when the value is zero and nothing was
// queued). The first connection of a path in a bounce puts the path on the shadow queue.
// `jump`: the gate jump a path-length-boundary connection sits on (~0 otherwise).
uint queueShadowRay(uint path, uint depth, uint kind, vec3 p0, vec3 p1, vec3 p2, uint segments, float value, float len,
                    uint jump) {
  if (value == 0.0) return 0xffffffffu;
  uint local = ((depth == kNoTape ? 0u : depth) & 1u) * kConnectionsPerVertex + kind;
  uint slot = shadowSlot(path, local);
  ShadowRay r;
  r.p0Value = vec4(p0, value);
  r.p1Length = vec4(p1, len);
  r.p2 = vec4(p2, 0.0);
  r.info = uvec4(path, segments, jump, depth);
  shadowRays[slot] = r;
#ifdef VKTG_DEFERRED_SHADOW_QUEUE
  deferredShadowPath = path;
  deferredShadowMask |= 1u << local;
#else
  uint batch = frame.pathInfo.w;
  if (atomicOr(rayQueues[3u * batch + path], 1u << local) == 0u) {
    uint queued = atomicAdd(counters[kCounterShadow], 1u);
    rayQueues[2u * batch + queued] = path;
  }
#endif
  return slot;
}

#ifdef VKTG_DEFERRED_SHADOW_QUEUE
// Puts the invocation's path on the shadow queue with the slots it filled, if any. No other
// invocation of the pass touches this path's mask, so a plain read and write suffice; the mask
// may already hold slots an earlier pass filled (a point sensor's connections from the sensor,
// queued with the camera rays), and then the path is on the queue already.
void flushShadowQueue() {
  if (deferredShadowMask == 0u) return;
  uint batch = frame.pathInfo.w;
  uint before = rayQueues[3u * batch + deferredShadowPath];
  rayQueues[3u * batch + deferredShadowPath] = before | deferredShadowMask;
  if (before != 0u) return;
  uint queued = atomicAdd(counters[kCounterShadow], 1u);
  rayQueues[2u * batch + queued] = deferredShadowPath;
}
#endif

// Point, geometric normal and shape of a hit, from its barycentrics (the exact surface point:
// path lengths are measured between these un-offset vertices).
struct SurfacePoint {
  vec3 position;
  vec3 normal;
  uint shape;
};

SurfacePoint surfacePoint(uint triangle, vec2 uv) {
  GpuTriangle t = loadTriangle(triangle);
  SurfacePoint sp;
  sp.position = (1.0 - uv.x - uv.y) * t.p0.xyz + uv.x * t.p1.xyz + uv.y * t.p2.xyz;
  sp.normal = normalize(cross(t.p1.xyz - t.p0.xyz, t.p2.xyz - t.p0.xyz));
  sp.shape = floatBitsToUint(t.p0.w);
  return sp;
}

// The first vertex of the path that can start an ellipsoidal connection: the frame's (0 at a
// point sensor, 1 behind a pinhole) unless an edge pass stored its own (kPathFlagEdgeArrival).
uint pathFirstEllipsoidVertex(PathState ps) {
  uint stored = ps.ids.w >> kPathEllipsoidShift;
  return stored > 0u ? stored - 1u : frame.pathInfo.y;
}

float powerHeuristic(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}
#endif
