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
VKTG_CHUNKS(float, filmSq, kBindingFilmSq)

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

// Adds to film and film-of-squares element i (atomic: many paths share a pixel).
void addToFilm(uint i, float value) {
  uint c = i >> frame.chunkShift.z;
  uint j = i & ((1u << frame.chunkShift.z) - 1u);
  float sq = value * value;
  if (c == 0u) { atomicAdd(film0[j], value); atomicAdd(filmSq0[j], sq); }
  else if (c == 1u) { atomicAdd(film1[j], value); atomicAdd(filmSq1[j], sq); }
  else if (c == 2u) { atomicAdd(film2[j], value); atomicAdd(filmSq2[j], sq); }
  else { atomicAdd(film3[j], value); atomicAdd(filmSq3[j], sq); }
}

float loadFilm(uint i) {
  uint c = i >> frame.chunkShift.z;
  uint j = i & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) return film0[j];
  if (c == 1u) return film1[j];
  if (c == 2u) return film2[j];
  return film3[j];
}

float loadFilmSq(uint i) {
  uint c = i >> frame.chunkShift.z;
  uint j = i & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) return filmSq0[j];
  if (c == 1u) return filmSq1[j];
  if (c == 2u) return filmSq2[j];
  return filmSq3[j];
}
#endif
