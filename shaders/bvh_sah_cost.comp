#version 460
#extension GL_GOOGLE_include_directive : require
// Pass bvh_sah_cost (scene update, the BVH quality check): the refit tree's surface-area-heuristic
// cost, as bvhSahCost in src/scene/bvh.cpp sums it on the host. An internal node's share is, for
// each child, the child box's area over the root box's area times the child's cost (its triangle
// count for a leaf, the traversal cost of 1 otherwise). Invocation t of T adds the shares of nodes
// t, t + T, t + 2T, ... in that order and writes its partial sum; the host adds the T partial sums
// in order (and the root's own visit). No barrier, no atomic: a given device sums the same boxes to
// the same bits, so an optimisation and its resumed run decide alike when to rebuild.
// Reads: BVH nodes (after refit_bvh). Writes: sahPartials[t]. Dispatch: ceil(T / kWorkgroupSize);
// push.args.x = T, push.args.w the node count.
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

float boxArea(vec3 lo, vec3 hi) {
  vec3 e = hi - lo;
  if (e.x < 0.0 || e.y < 0.0 || e.z < 0.0) return 0.0;
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

float childCost(uint child) {
  uint count = floatBitsToUint(loadBvhNode(child).rightMinCount.w);
  return count > 0u ? float(count) : 1.0;
}

void main() {
  uint t = gl_GlobalInvocationID.x, invocations = push.args.x;
  if (t >= invocations) return;
  GpuBvhNode root = loadBvhNode(0u);
  float rootArea = max(boxArea(min(root.leftMinLeftIndex.xyz, root.rightMinCount.xyz),
                               max(root.leftMaxRightIndex.xyz, root.rightMaxFirst.xyz)),
                       1e-30);
  float sum = 0.0;
  for (uint i = t; i < push.args.w; i += invocations) {
    GpuBvhNode n = loadBvhNode(i);
    if (floatBitsToUint(n.rightMinCount.w) != 0u) continue;  // a leaf: its parent counted it
    sum += (boxArea(n.leftMinLeftIndex.xyz, n.leftMaxRightIndex.xyz) * childCost(floatBitsToUint(n.leftMinLeftIndex.w)) +
            boxArea(n.rightMinCount.xyz, n.rightMaxFirst.xyz) * childCost(floatBitsToUint(n.leftMaxRightIndex.w))) /
           rootArea;
  }
  sahPartials[t] = sum;
}
