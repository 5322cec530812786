// Descriptor declarations of set 0 (layouts in include/vktg/gpu/shared.h) and accessors that
// hide the chunking of large buffers (each chunk stays under maxStorageBufferRange; lavapipe has
// no descriptor indexing, so chunks are separate bindings selected by a switch).
#ifndef VKTG_BINDINGS_GLSL
#define VKTG_BINDINGS_GLSL
#include "vktg/gpu/shared.h"

layout(std140, set = 0, binding = kBindingFrame) uniform FrameBlock { FrameUniforms frame; };

#define VKTG_CHUNKS(Type, name, base)                                                      \
  layout(std430, set = 0, binding = base + 0) buffer name##Chunk0 { Type name##0[]; };     \
  layout(std430, set = 0, binding = base + 1) buffer name##Chunk1 { Type name##1[]; };     \
  layout(std430, set = 0, binding = base + 2) buffer name##Chunk2 { Type name##2[]; };     \
  layout(std430, set = 0, binding = base + 3) buffer name##Chunk3 { Type name##3[]; };

VKTG_CHUNKS(GpuTriangle, triangles, kBindingTriangles)
VKTG_CHUNKS(GpuBvhNode, bvhNodes, kBindingBvhNodes)
VKTG_CHUNKS(float, film, kBindingFilm)

layout(std430, set = 0, binding = kBindingTriangleVerts) readonly buffer TriangleVertsBlock { uvec4 triangleVerts[]; };
layout(std430, set = 0, binding = kBindingVertices) readonly buffer VerticesBlock { vec4 vertices[]; };
layout(std430, set = 0, binding = kBindingShapes) readonly buffer ShapesBlock { GpuShape shapes[]; };
layout(std430, set = 0, binding = kBindingMaterials) readonly buffer MaterialsBlock { GpuMaterial materials[]; };
layout(std430, set = 0, binding = kBindingLights) readonly buffer LightsBlock { GpuLight lights[]; };
layout(std430, set = 0, binding = kBindingPaths) buffer PathsBlock { PathState paths[]; };
layout(std430, set = 0, binding = kBindingHits) buffer HitsBlock { HitRecord hits[]; };
layout(std430, set = 0, binding = kBindingRayQueues) buffer RayQueuesBlock { uint rayQueues[]; };
layout(std430, set = 0, binding = kBindingShadowQueue) buffer ShadowQueueBlock { ShadowRay shadowRays[]; };
layout(std430, set = 0, binding = kBindingCounters) buffer CountersBlock { uint counters[]; };
layout(std430, set = 0, binding = kBindingDispatchArgs) buffer DispatchArgsBlock { uint dispatchArgs[]; };
layout(std430, set = 0, binding = kBindingPathAccum) buffer PathAccumBlock { float pathAccum[]; };

#ifdef VKTG_DERIVATIVE
layout(std430, set = 0, binding = kBindingVertexVelocity) readonly buffer VertexVelocityBlock { vec4 vertexVelocity[]; };
layout(std430, set = 0, binding = kBindingLanes) readonly buffer LanesBlock { GpuLane lanes[]; };
layout(std430, set = 0, binding = kBindingPathDerivs) buffer PathDerivsBlock { PathDerivative pathDerivs[]; };
layout(std430, set = 0, binding = kBindingShadowDerivs) buffer ShadowDerivsBlock { vec2 shadowDerivs[]; };
#endif

GpuTriangle loadTriangle(uint i) {
  uint c = i >> frame.chunkShift.x;
  uint j = i & ((1u << frame.chunkShift.x) - 1u);
  if (c == 0u) return triangles0[j];
  if (c == 1u) return triangles1[j];
  if (c == 2u) return triangles2[j];
  return triangles3[j];
}

GpuBvhNode loadBvhNode(uint i) {
  uint c = i >> frame.chunkShift.y;
  uint j = i & ((1u << frame.chunkShift.y) - 1u);
  if (c == 0u) return bvhNodes0[j];
  if (c == 1u) return bvhNodes1[j];
  if (c == 2u) return bvhNodes2[j];
  return bvhNodes3[j];
}

// Film element i: 4 floats at 4i (see kBindingFilm), always in one chunk (chunks hold a
// power-of-two count of floats).
vec4 loadFilm(uint i) {
  uint k = kFilmFloatsPerElement * i;
  uint c = k >> frame.chunkShift.z;
  uint j = k & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) return vec4(film0[j], film0[j + 1u], film0[j + 2u], film0[j + 3u]);
  if (c == 1u) return vec4(film1[j], film1[j + 1u], film1[j + 2u], film1[j + 3u]);
  if (c == 2u) return vec4(film2[j], film2[j + 1u], film2[j + 2u], film2[j + 3u]);
  return vec4(film3[j], film3[j + 1u], film3[j + 2u], film3[j + 3u]);
}

void storeFilm(uint i, vec4 v) {
  uint k = kFilmFloatsPerElement * i;
  uint c = k >> frame.chunkShift.z;
  uint j = k & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) { film0[j] = v.x; film0[j + 1u] = v.y; film0[j + 2u] = v.z; film0[j + 3u] = v.w; }
  else if (c == 1u) { film1[j] = v.x; film1[j + 1u] = v.y; film1[j + 2u] = v.z; film1[j + 3u] = v.w; }
  else if (c == 2u) { film2[j] = v.x; film2[j + 1u] = v.y; film2[j + 2u] = v.z; film2[j + 3u] = v.w; }
  else { film3[j] = v.x; film3[j + 1u] = v.y; film3[j + 2u] = v.z; film3[j + 3u] = v.w; }
}
#endif
