#version 460
#extension GL_GOOGLE_include_directive : require
// Pass intersect_closest: closest hit of every queued ray.
// Reads: ray queue (depth parity push.args.z & 1), paths[].position/direction, scene BVH.
// Writes: hits[path] (t < 0 for a miss). Dispatch: indirect, from the queue's counter.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/bvh.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint parity = push.args.z & 1u;
  uint index = gl_GlobalInvocationID.x;
  if (index >= counters[kCounterRays0 + parity]) return;
  uint path = rayQueues[parity * frame.pathInfo.w + index];
  PathState ps = loadPath(path);
  // Rays leave the exact (un-offset) vertex; tMin skips the surface they start on. The camera
  // and the point sensor are not on a surface.
  float tMin = ps.ids.z == 0u ? 0.0 : frame.sceneInfo.x;
  HitRecord hit;
  if (!traceClosest(ps.position.xyz, ps.direction.xyz, tMin, kInfinity, hit)) hit.tuvTriangle.x = -1.0;
  hits[path] = hit;
}
