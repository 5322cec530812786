#version 460
#extension GL_GOOGLE_include_directive : require
// Pass update_triangles (scene update): copies the moved vertices into the BVH-ordered triangle
// array the traversal reads, with each triangle's area; triangles of shapes nothing moves are left
// as they are. Reads: triangleVerts, vertices, shapes. Writes: triangles.
// Dispatch: ceil(triangles / kWorkgroupSize).
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.sceneCounts.x) return;
  uvec4 ids = triangleVerts[i];
  if ((shapes[ids.w].flags & kShapeMoves) == 0u) return;
  GpuTriangle t = loadTriangle(i);
  t.p0.xyz = vertices[ids.x].xyz;
  t.p1.xyz = vertices[ids.y].xyz;
  t.p2.xyz = vertices[ids.z].xyz;
  t.p2.w = 0.5 * length(cross(t.p1.xyz - t.p0.xyz, t.p2.xyz - t.p0.xyz));
  storeTriangle(i, t);
}
