#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: bsdfEval and bsdfPdf on a list of configurations.
// In per invocation (16 words): material (type, albedo, roughness, ior), n.xyz + pad, wi.xyz + pad,
// wo.xyz + pad. Out per invocation (2 words): bsdfEval, bsdfPdf.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/bsdf.glsl"

layout(local_size_x = kWorkgroupSize) in;

vec3 loadVec3(uint w) {
  return vec3(uintBitsToFloat(testIn[w]), uintBitsToFloat(testIn[w + 1u]), uintBitsToFloat(testIn[w + 2u]));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint b = 16u * i;
  GpuMaterial m;
  m.type = testIn[b];
  m.albedo = uintBitsToFloat(testIn[b + 1u]);
  m.roughness = uintBitsToFloat(testIn[b + 2u]);
  m.ior = uintBitsToFloat(testIn[b + 3u]);
  vec3 n = loadVec3(b + 4u);
  vec3 wi = loadVec3(b + 8u);
  vec3 wo = loadVec3(b + 12u);
  testOut[2u * i] = floatBitsToUint(bsdfEval(m, n, wi, wo));
  testOut[2u * i + 1u] = floatBitsToUint(bsdfPdf(m, n, wi, wo));
}
