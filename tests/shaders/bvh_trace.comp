#version 460
#extension GL_GOOGLE_include_directive : require
// Traces one ray per invocation through the uploaded scene's BVH (tests/gpu_bvh.cpp).
// In  (8 words per ray):  origin xyz, dir xyz, tMin, tMax (float bits).
// Out (5 words per ray):  traceClosest's t (-1 on a miss), u, v, triangle (uint, leaf order),
//                         then traceAny (1 or 0).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/bvh.glsl"

layout(local_size_x = kWorkgroupSize) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint b = 8u * i;
  vec3 origin = vec3(uintBitsToFloat(testIn[b]), uintBitsToFloat(testIn[b + 1u]), uintBitsToFloat(testIn[b + 2u]));
  vec3 dir = vec3(uintBitsToFloat(testIn[b + 3u]), uintBitsToFloat(testIn[b + 4u]), uintBitsToFloat(testIn[b + 5u]));
  float tMin = uintBitsToFloat(testIn[b + 6u]);
  float tMax = uintBitsToFloat(testIn[b + 7u]);
  HitRecord hit;
  traceClosest(origin, dir, tMin, tMax, hit);
  bool any = traceAny(origin, dir, tMin, tMax);
  uint triangle = floatBitsToUint(hit.tuvTriangle.w);
  uint o = 5u * i;
  testOut[o] = floatBitsToUint(hit.tuvTriangle.x);
  testOut[o + 1u] = floatBitsToUint(hit.tuvTriangle.y);
  testOut[o + 2u] = floatBitsToUint(hit.tuvTriangle.z);
  testOut[o + 3u] = triangle;
  testOut[o + 4u] = any ? 1u : 0u;
}
