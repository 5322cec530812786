// Descriptor declarations of the scene-update layout (include/vktg/gpu/shared.h, kUpdateBinding*):
// the scene part of set 0 (lib/scene_bindings.glsl) plus what moves it: base positions, per-vertex
// op lists, the parameter ops and θ, the BVH refit order, the edge list, the 4-wide tree and the
// refit tree's SAH partial sums.
#ifndef VKTG_UPDATE_BINDINGS_GLSL
#define VKTG_UPDATE_BINDINGS_GLSL
#include "lib/scene_bindings.glsl"

layout(std430, set = 0, binding = kUpdateBindingBasePositions) readonly buffer BaseBlock { vec4 basePositions[]; };
layout(std430, set = 0, binding = kUpdateBindingVertexOps) readonly buffer VertexOpsBlock { uvec2 vertexOps[]; };
layout(std430, set = 0, binding = kUpdateBindingOpList) readonly buffer OpListBlock { uint opList[]; };
layout(std430, set = 0, binding = kUpdateBindingParameterOps) readonly buffer ParameterOpsBlock { GpuParameterOp parameterOps[]; };
layout(std430, set = 0, binding = kUpdateBindingTheta) readonly buffer ThetaBlock { float theta[]; };
layout(std430, set = 0, binding = kUpdateBindingRefitOrder) readonly buffer RefitOrderBlock { uint refitOrder[]; };
layout(std430, set = 0, binding = kUpdateBindingEdges) buffer EdgesBlock { GpuEdge edges[]; };
layout(std430, set = 0, binding = kUpdateBindingEdgeFaces) readonly buffer EdgeFacesBlock { uvec4 edgeFaces[]; };
layout(std430, set = 0, binding = kUpdateBindingWideBvhNodes) buffer WideBvhNodesBlock { GpuWideBvhNode wideBvhNodes[]; };
layout(std430, set = 0, binding = kUpdateBindingSahPartials) writeonly buffer SahPartialsBlock { float sahPartials[]; };

void storeTriangle(uint i, GpuTriangle t) {
  if (kSpecSingleChunkValue != 0u) {
    triangles0[i] = t;
    return;
  }
  uint c = i >> frame.chunkShift.x;
  uint j = i & ((1u << frame.chunkShift.x) - 1u);
  if (c == 0u) triangles0[j] = t;
  else if (c == 1u) triangles1[j] = t;
  else if (c == 2u) triangles2[j] = t;
  else triangles3[j] = t;
}

void storeBvhNode(uint i, GpuBvhNode n) {
  if (kSpecSingleChunkValue != 0u) {
    bvhNodes0[i] = n;
    return;
  }
  uint c = i >> frame.chunkShift.y;
  uint j = i & ((1u << frame.chunkShift.y) - 1u);
  if (c == 0u) bvhNodes0[j] = n;
  else if (c == 1u) bvhNodes1[j] = n;
  else if (c == 2u) bvhNodes2[j] = n;
  else bvhNodes3[j] = n;
}
#endif
