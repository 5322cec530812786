#version 460
#extension GL_GOOGLE_include_directive : require
// Pass update_edges (scene update): moves the edge list with the vertices. An edge's ends are its
// two vertices; each face's inward direction is the part of (opposite vertex - first end)
// perpendicular to the edge, normalised (silhouetteEdges' cross(n, e), turned into the face, is the
// same direction). The selection CDF and probabilities (w components) stay as built: any fixed
// choice of edges is unbiased, and sample_edges divides by the current length.
// Reads: edgeFaces, vertices. Writes: edges. Dispatch: ceil(edges / kWorkgroupSize).
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;

vec3 inwardTowards(vec3 p0, vec3 e, uint opposite) {
  if (opposite == 0xffffffffu || !(dot(e, e) > 0.0)) return vec3(0.0);
  vec3 d = vertices[opposite].xyz - p0;
  vec3 across = d - e * (dot(d, e) / dot(e, e));
  float len = length(across);
  return len > 0.0 ? across / len : vec3(0.0);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.edgeInfo.x) return;
  GpuEdge edge = edges[i];
  vec3 p0 = vertices[floatBitsToUint(edge.p0.w)].xyz;
  vec3 p1 = vertices[floatBitsToUint(edge.p1.w)].xyz;
  uvec4 faces = edgeFaces[i];
  edge.p0.xyz = p0;
  edge.p1.xyz = p1;
  edge.inward0.xyz = inwardTowards(p0, p1 - p0, faces.x);
  edge.inward1.xyz = inwardTowards(p0, p1 - p0, faces.y);
  edges[i] = edge;
}
