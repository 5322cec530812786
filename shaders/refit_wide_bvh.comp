#version 460
#extension GL_GOOGLE_include_directive : require
// Pass refit_wide_bvh (scene update, after every level of refit_bvh): the 4-wide tree's child boxes
// (GpuWideBvhNode, the traversal of CPU devices) copied from the refit binary tree, which keeps each
// of them where GpuWideBvhNode.source says. A root over one leaf keeps its unbounded box.
// Reads: binary BVH nodes, wide nodes. Writes: wide node boxes. Dispatch: ceil(wide nodes /
// kWorkgroupSize); push.args.w the number of wide nodes.
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  GpuWideBvhNode wide = wideBvhNodes[i];
  for (int k = 0; k < 4; ++k) {
    uint source = wide.source[k];
    if (source == kWideBvhEmpty) continue;
    GpuBvhNode n = loadBvhNode(source >> 1u);
    bool right = (source & 1u) != 0u;
    vec3 lo = right ? n.rightMinCount.xyz : n.leftMinLeftIndex.xyz;
    vec3 hi = right ? n.rightMaxFirst.xyz : n.leftMaxRightIndex.xyz;
    wide.loX[k] = lo.x;
    wide.loY[k] = lo.y;
    wide.loZ[k] = lo.z;
    wide.hiX[k] = hi.x;
    wide.hiY[k] = hi.y;
    wide.hiZ[k] = hi.z;
  }
  wideBvhNodes[i] = wide;
}
