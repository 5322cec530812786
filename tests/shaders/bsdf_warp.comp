#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the warps of lib/warp.glsl on hashed uniforms, and basisFromNormal on given normals.
// In: seed (word 0), then per invocation a normal (4 words from word 4). Out per invocation
// (16 words): cosine-hemisphere direction (3), uniform-sphere direction (3), triangle
// barycentrics (2), basis t (3), basis b (3), 2 pad. Random numbers: hash4(i, seed, 1, 0).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/rng.glsl"
#include "lib/warp.glsl"

layout(local_size_x = kWorkgroupSize) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uvec4 h = hash4(uvec4(i, testIn[0], 1u, 0u));
  vec4 u = vec4(bitsToUnit(h.x), bitsToUnit(h.y), bitsToUnit(h.z), bitsToUnit(h.w));
  uint w = 4u + 4u * i;
  vec3 n = vec3(uintBitsToFloat(testIn[w]), uintBitsToFloat(testIn[w + 1u]), uintBitsToFloat(testIn[w + 2u]));
  vec3 c = sampleCosineHemisphere(u.xy);
  vec3 s = sampleUniformSphere(u.zw);
  vec2 bary = sampleTriangleBarycentrics(u.xz);
  vec3 t;
  vec3 b;
  basisFromNormal(n, t, b);
  float outv[16] = float[16](c.x, c.y, c.z, s.x, s.y, s.z, bary.x, bary.y, t.x, t.y, t.z, b.x, b.y, b.z, 0.0, 0.0);
  for (uint k = 0u; k < 16u; ++k) testOut[16u * i + k] = floatBitsToUint(outv[k]);
}
