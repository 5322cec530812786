// Descriptor declarations of the scene part of set 0 (bindings 0-13: frame and scene, laid out in
// include/vktg/gpu/shared.h), shared by the render layout (lib/bindings.glsl) and the scene-update
// layout (lib/update_bindings.glsl), with accessors that hide the chunking of large buffers (each
// chunk stays under maxStorageBufferRange; lavapipe has no descriptor indexing, so chunks are
// separate bindings selected by a switch). Where every chunked buffer holds one chunk (nearly every
// scene; kSpecSingleChunk) the accessors index chunk 0 directly: a CPU device runs all four arms of
// the switch with the lanes masked, which cost lavapipe's BVH traversal 40% of its rays per second.
#ifndef VKTG_SCENE_BINDINGS_GLSL
#define VKTG_SCENE_BINDINGS_GLSL
#include "vktg/gpu/shared.h"
#include "lib/specialization.glsl"

// The frame block is a storage buffer, not a uniform buffer: lavapipe inlines the uniform-buffer
// values its branches read and compiles, and keeps, a shader variant per distinct set of them, so a
// uniform frame block grew the process by megabytes per render (tests/render_memory.cpp).
// A render of several views appends a record per view (lib/view.glsl).
layout(std430, set = 0, binding = kBindingFrame) readonly buffer FrameBlock {
  FrameUniforms frame;
  vec4 frameViews[];
};

#define VKTG_CHUNKS(Type, name, base)                                                      \
  layout(std430, set = 0, binding = base + 0) buffer name##Chunk0 { Type name##0[]; };     \
  layout(std430, set = 0, binding = base + 1) buffer name##Chunk1 { Type name##1[]; };     \
  layout(std430, set = 0, binding = base + 2) buffer name##Chunk2 { Type name##2[]; };     \
  layout(std430, set = 0, binding = base + 3) buffer name##Chunk3 { Type name##3[]; };

VKTG_CHUNKS(GpuTriangle, triangles, kBindingTriangles)
VKTG_CHUNKS(GpuBvhNode, bvhNodes, kBindingBvhNodes)
// The same triangles and nodes as 16-byte texels (kSpecSceneTexels; shared.h says why).
layout(set = 0, binding = kBindingTriangleTexels) uniform usamplerBuffer triangleTexels;
layout(set = 0, binding = kBindingBvhNodeTexels) uniform usamplerBuffer bvhNodeTexels;
layout(set = 0, binding = kBindingWideBvhTexels) uniform usamplerBuffer wideBvhTexels;

vec4 texelVec4(usamplerBuffer texels, int i) { return uintBitsToFloat(texelFetch(texels, i)); }

layout(std430, set = 0, binding = kBindingTriangleVerts) readonly buffer TriangleVertsBlock { uvec4 triangleVerts[]; };
layout(std430, set = 0, binding = kBindingVertices) buffer VerticesBlock { vec4 vertices[]; };
layout(std430, set = 0, binding = kBindingShapes) readonly buffer ShapesBlock { GpuShape shapes[]; };
layout(std430, set = 0, binding = kBindingMaterials) readonly buffer MaterialsBlock { GpuMaterial materials[]; };
layout(std430, set = 0, binding = kBindingLights) readonly buffer LightsBlock { GpuLight lights[]; };

GpuTriangle loadTriangle(uint i) {
  if (kSpecSceneTexelsValue != 0u) {
    int t = 3 * int(i);
    return GpuTriangle(texelVec4(triangleTexels, t), texelVec4(triangleTexels, t + 1), texelVec4(triangleTexels, t + 2));
  }
  if (kSpecSingleChunkValue != 0u) return triangles0[i];
  uint c = i >> frame.chunkShift.x;
  uint j = i & ((1u << frame.chunkShift.x) - 1u);
  if (c == 0u) return triangles0[j];
  if (c == 1u) return triangles1[j];
  if (c == 2u) return triangles2[j];
  return triangles3[j];
}

GpuBvhNode loadBvhNode(uint i) {
  if (kSpecSceneTexelsValue != 0u) {
    int t = 4 * int(i);
    return GpuBvhNode(texelVec4(bvhNodeTexels, t), texelVec4(bvhNodeTexels, t + 1), texelVec4(bvhNodeTexels, t + 2),
                      texelVec4(bvhNodeTexels, t + 3));
  }
  if (kSpecSingleChunkValue != 0u) return bvhNodes0[i];
  uint c = i >> frame.chunkShift.y;
  uint j = i & ((1u << frame.chunkShift.y) - 1u);
  if (c == 0u) return bvhNodes0[j];
  if (c == 1u) return bvhNodes1[j];
  if (c == 2u) return bvhNodes2[j];
  return bvhNodes3[j];
}
#include "lib/view.glsl"
#endif
