// Descriptor declarations of set 0 in the render layout (include/vktg/gpu/shared.h): the scene
// part (lib/scene_bindings.glsl), the wavefront, the film, and the bindings 25-28 each kind of pass
// gives its own meaning (derivative lanes, adjoint buffers, edge records).
#ifndef VKTG_BINDINGS_GLSL
#define VKTG_BINDINGS_GLSL
#include "lib/scene_bindings.glsl"

VKTG_CHUNKS(float, film, kBindingFilm)

layout(std430, set = 0, binding = kBindingPaths) buffer PathsBlock { PathState paths[]; };
layout(std430, set = 0, binding = kBindingHits) buffer HitsBlock { HitRecord hits[]; };
layout(std430, set = 0, binding = kBindingRayQueues) buffer RayQueuesBlock { uint rayQueues[]; };
layout(std430, set = 0, binding = kBindingShadowQueue) buffer ShadowQueueBlock { ShadowRay shadowRays[]; };
layout(std430, set = 0, binding = kBindingCounters) buffer CountersBlock { uint counters[]; };
layout(std430, set = 0, binding = kBindingDispatchArgs) buffer DispatchArgsBlock { uint dispatchArgs[]; };
layout(std430, set = 0, binding = kBindingPathAccum) buffer PathAccumBlock { float pathAccum[]; };

// The same path states and hits as 16-byte texels (kSpecWaveTexels; shared.h says why). A pass
// reads them only where earlier passes wrote them: texel reads need not see its own writes.
layout(set = 0, binding = kBindingPathTexels) uniform usamplerBuffer pathTexels;
layout(set = 0, binding = kBindingHitTexels) uniform usamplerBuffer hitTexels;

PathState loadPath(uint p) {
  if (kSpecWaveTexelsValue == 0u) return paths[p];
  int t = 6 * int(p);
  return PathState(texelVec4(pathTexels, t), texelVec4(pathTexels, t + 1), texelVec4(pathTexels, t + 2),
                   texelVec4(pathTexels, t + 3), texelFetch(pathTexels, t + 4), texelVec4(pathTexels, t + 5));
}

HitRecord loadHit(uint p) {
  if (kSpecWaveTexelsValue == 0u) return hits[p];
  return HitRecord(texelVec4(hitTexels, int(p)));
}

// Forward-mode lanes: what each lane differentiates (VKTG_LANE_INPUTS, also read by
// accumulate_splats), and the per-path derivative state (VKTG_DERIVATIVE).
#if defined(VKTG_DERIVATIVE) || defined(VKTG_LANE_INPUTS)
layout(std430, set = 0, binding = kBindingVertexVelocity) readonly buffer VertexVelocityBlock { vec4 vertexVelocity[]; };
layout(std430, set = 0, binding = kBindingLanes) readonly buffer LanesBlock { GpuLane lanes[]; };
#endif
#ifdef VKTG_DERIVATIVE
layout(std430, set = 0, binding = kBindingPathDerivs) buffer PathDerivsBlock { PathDerivative pathDerivs[]; };
layout(std430, set = 0, binding = kBindingShadowDerivs) buffer ShadowDerivsBlock { vec2 shadowDerivs[]; };
#endif

// Film element i: 4 floats at 4i (see kBindingFilm), always in one chunk (chunks hold a
// power-of-two count of floats).
vec4 loadFilm(uint i) {
  uint k = kFilmFloatsPerElement * i;
  if (kSpecSingleChunkValue != 0u) return vec4(film0[k], film0[k + 1u], film0[k + 2u], film0[k + 3u]);
  uint c = k >> frame.chunkShift.z;
  uint j = k & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) return vec4(film0[j], film0[j + 1u], film0[j + 2u], film0[j + 3u]);
  if (c == 1u) return vec4(film1[j], film1[j + 1u], film1[j + 2u], film1[j + 3u]);
  if (c == 2u) return vec4(film2[j], film2[j + 1u], film2[j + 2u], film2[j + 3u]);
  return vec4(film3[j], film3[j + 1u], film3[j + 2u], film3[j + 3u]);
}

void storeFilm(uint i, vec4 v) {
  uint k = kFilmFloatsPerElement * i;
  if (kSpecSingleChunkValue != 0u) {
    film0[k] = v.x;
    film0[k + 1u] = v.y;
    film0[k + 2u] = v.z;
    film0[k + 3u] = v.w;
    return;
  }
  uint c = k >> frame.chunkShift.z;
  uint j = k & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) { film0[j] = v.x; film0[j + 1u] = v.y; film0[j + 2u] = v.z; film0[j + 3u] = v.w; }
  else if (c == 1u) { film1[j] = v.x; film1[j + 1u] = v.y; film1[j + 2u] = v.z; film1[j + 3u] = v.w; }
  else if (c == 2u) { film2[j] = v.x; film2[j + 1u] = v.y; film2[j + 2u] = v.z; film2[j + 3u] = v.w; }
  else { film3[j] = v.x; film3[j + 1u] = v.y; film3[j + 2u] = v.z; film3[j + 3u] = v.w; }
}
#endif
