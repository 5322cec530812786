#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: bsdfEvalDual (shaders/lib/bsdf_dual.glsl) next to bsdfEval (shaders/lib/bsdf.glsl).
// In per invocation (32 words): material (type, albedo, roughness, ior), the derivatives of albedo,
// roughness and ior, -, then n, dn, wi, dwi, wo, dwo (xyz + pad each).
// Out per invocation (4 words): dual value, dual derivative, bsdfEval, zero.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/bsdf_dual.glsl"

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
vec3 inV(uint i) { return vec3(inF(i), inF(i + 1u), inF(i + 2u)); }

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint b = 32u * i;
  GpuMaterial m;
  m.type = testIn[b];
  m.albedo = inF(b + 1u);
  m.roughness = inF(b + 2u);
  m.ior = inF(b + 3u);
  Dual albedo = dual(m.albedo, inF(b + 4u));
  Dual roughness = dual(m.roughness, inF(b + 5u));
  Dual ior = dual(m.ior, inF(b + 6u));
  Dual3 n = dual3(inV(b + 8u), inV(b + 12u));
  Dual3 wi = dual3(inV(b + 16u), inV(b + 20u));
  Dual3 wo = dual3(inV(b + 24u), inV(b + 28u));
  Dual f = bsdfEvalDual(m, albedo, roughness, ior, n, wi, wo);
  uint o = 4u * i;
  testOut[o] = floatBitsToUint(f.v);
  testOut[o + 1u] = floatBitsToUint(f.d);
  testOut[o + 2u] = floatBitsToUint(bsdfEval(m, n.v, wi.v, wo.v));
  testOut[o + 3u] = 0u;
}
