#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: draws bsdfSample for one (material, n, wi) per dispatch and, at each sampled
// direction, evaluates bsdfEval and bsdfPdf so the host can check their consistency per sample.
// In (words): material (type, albedo, roughness, ior), n.xyz + pad, wi.xyz + pad, seed + 3 pad.
// Out per invocation i (8 words): wo.xyz, weight, pdf, flags (1: sampled, 2: transmitted),
// bsdfEval(wo), bsdfPdf(wo). Random numbers: hash4(i, seed, 0, 0).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/rng.glsl"
#include "lib/bsdf.glsl"

layout(local_size_x = kWorkgroupSize) in;

vec3 loadVec3(uint w) {
  return vec3(uintBitsToFloat(testIn[w]), uintBitsToFloat(testIn[w + 1u]), uintBitsToFloat(testIn[w + 2u]));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  GpuMaterial m;
  m.type = testIn[0];
  m.albedo = uintBitsToFloat(testIn[1]);
  m.roughness = uintBitsToFloat(testIn[2]);
  m.ior = uintBitsToFloat(testIn[3]);
  vec3 n = loadVec3(4u);
  vec3 wi = loadVec3(8u);
  uvec4 h = hash4(uvec4(i, testIn[12], 0u, 0u));
  vec3 u = vec3(bitsToUnit(h.x), bitsToUnit(h.y), bitsToUnit(h.z));

  BsdfSample s;
  bool ok = bsdfSample(m, n, wi, u, s);
  uint o = 8u * i;
  testOut[o + 0u] = floatBitsToUint(s.wo.x);
  testOut[o + 1u] = floatBitsToUint(s.wo.y);
  testOut[o + 2u] = floatBitsToUint(s.wo.z);
  testOut[o + 3u] = floatBitsToUint(s.weight);
  testOut[o + 4u] = floatBitsToUint(s.pdf);
  testOut[o + 5u] = (ok ? 1u : 0u) | (s.transmitted ? 2u : 0u);
  testOut[o + 6u] = floatBitsToUint(ok ? bsdfEval(m, n, wi, s.wo) : 0.0);
  testOut[o + 7u] = floatBitsToUint(ok ? bsdfPdf(m, n, wi, s.wo) : 0.0);
}
