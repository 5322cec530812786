#version 460
#extension GL_GOOGLE_include_directive : require
// Pass bench_trace (`vktg bench trace` only): one ray per invocation through the scene's BVH, the
// traversal every render pass uses, so its rays per second are the renderer's.
// Reads: pathAccum as 8 floats per ray (origin xyz, tMin, direction xyz, tMax), scene BVH.
// Writes: hits[ray]: closest hit (t < 0 for a miss), or with push.args.y != 0 the any-hit answer
// in x (1 or -1). push.args.x: the number of rays. Dispatch: ceil(rays / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/bvh.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= push.args.x) return;
  uint b = 8u * ray;
  vec3 origin = vec3(pathAccum[b], pathAccum[b + 1u], pathAccum[b + 2u]);
  vec3 direction = vec3(pathAccum[b + 4u], pathAccum[b + 5u], pathAccum[b + 6u]);
  float tMin = pathAccum[b + 3u], tMax = pathAccum[b + 7u];
  HitRecord hit;
  if (push.args.y != 0u) {
    hit.tuvTriangle = vec4(traceAny(origin, direction, tMin, tMax) ? 1.0 : -1.0, 0.0, 0.0, 0.0);
  } else if (!traceClosest(origin, direction, tMin, tMax, hit)) {
    hit.tuvTriangle.x = -1.0;
  }
  hits[ray] = hit;
}
