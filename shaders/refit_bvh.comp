#version 460
#extension GL_GOOGLE_include_directive : require
// Pass refit_bvh (scene update): one level of the bottom-up refit (refitBvh in src/scene/bvh.cpp is
// the host twin). Each internal node of the level stores both children's boxes: a leaf child's is
// the union of its triangles' padded boxes (lib/intersect.glsl: the boxes the triangle test checks
// its t against, so the traversal still never culls a box holding an accepted hit), an internal
// child's the union of the two boxes it stores, which the previous (deeper) level has refit. Minima
// and maxima are exact, so the same positions always give the same tree.
// Reads: refitOrder[push.args.x .. + push.args.w), BVH nodes, triangles. Writes: BVH node boxes.
// Dispatch: ceil(nodes of the level / kWorkgroupSize).
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"
#include "lib/intersect.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void boxOf(uint node, out vec3 lo, out vec3 hi) {
  GpuBvhNode n = loadBvhNode(node);
  uint count = floatBitsToUint(n.rightMinCount.w);
  if (count == 0u) {
    lo = min(n.leftMinLeftIndex.xyz, n.rightMinCount.xyz);
    hi = max(n.leftMaxRightIndex.xyz, n.rightMaxFirst.xyz);
    return;
  }
  uint first = floatBitsToUint(n.rightMaxFirst.w);
  lo = vec3(kInfinity);
  hi = vec3(-kInfinity);
  for (uint i = first; i < first + count; ++i) {
    GpuTriangle t = loadTriangle(i);
    vec3 l, h;
    trianglePaddedBox(t.p0.xyz, t.p1.xyz, t.p2.xyz, l, h);
    lo = min(lo, l);
    hi = max(hi, h);
  }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  uint node = refitOrder[push.args.x + i];
  GpuBvhNode n = loadBvhNode(node);
  vec3 lo, hi;
  boxOf(floatBitsToUint(n.leftMinLeftIndex.w), lo, hi);
  n.leftMinLeftIndex.xyz = lo;
  n.leftMaxRightIndex.xyz = hi;
  boxOf(floatBitsToUint(n.leftMaxRightIndex.w), lo, hi);
  n.rightMinCount.xyz = lo;
  n.rightMaxFirst.xyz = hi;
  storeBvhNode(node, n);
}
