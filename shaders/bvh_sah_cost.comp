#version 460
#extension GL_GOOGLE_include_directive : require
// Pass bvh_sah_cost (scene update, the BVH quality check): the refit tree's surface-area-heuristic
// cost, as bvhSahCost in src/scene/bvh.cpp sums it on the host. Each invocation takes one node; an
// internal node adds, for each child, the child box's area over the root box's area times the
// child's cost (its triangle count for a leaf, the traversal cost of 1 otherwise). A workgroup sums
// its nodes' shares in shared memory in a fixed order and writes one partial sum; the host adds the
// partial sums in order (and the root's own visit). A given device sums the same boxes to the same
// bits, so an optimisation and its resumed run decide alike when to rebuild.
// Reads: BVH nodes (after refit_bvh). Writes: sahPartials[workgroup]. Dispatch: ceil(nodes /
// kWorkgroupSize); push.args.w the node count.
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

shared float shares[kWorkgroupSize];

float boxArea(vec3 lo, vec3 hi) {
  vec3 e = hi - lo;
  if (e.x < 0.0 || e.y < 0.0 || e.z < 0.0) return 0.0;
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

uint childCost(uint child) { return floatBitsToUint(loadBvhNode(child).rightMinCount.w); }

void main() {
  uint i = gl_GlobalInvocationID.x;
  float share = 0.0;
  if (i < push.args.w) {
    GpuBvhNode n = loadBvhNode(i);
    if (floatBitsToUint(n.rightMinCount.w) == 0u) {
      GpuBvhNode root = loadBvhNode(0u);
      float rootArea = max(boxArea(min(root.leftMinLeftIndex.xyz, root.rightMinCount.xyz),
                                   max(root.leftMaxRightIndex.xyz, root.rightMaxFirst.xyz)),
                           1e-30);
      uint left = childCost(floatBitsToUint(n.leftMinLeftIndex.w));
      uint right = childCost(floatBitsToUint(n.leftMaxRightIndex.w));
      share = boxArea(n.leftMinLeftIndex.xyz, n.leftMaxRightIndex.xyz) / rootArea * (left > 0u ? float(left) : 1.0) +
              boxArea(n.rightMinCount.xyz, n.rightMaxFirst.xyz) / rootArea * (right > 0u ? float(right) : 1.0);
    }
  }
  uint lane = gl_LocalInvocationID.x;
  shares[lane] = share;
  barrier();
  for (uint stride = kWorkgroupSize / 2u; stride > 0u; stride /= 2u) {
    if (lane < stride) shares[lane] += shares[lane + stride];
    barrier();
  }
  if (lane == 0u) sahPartials[gl_WorkGroupID.x] = shares[0];
}
