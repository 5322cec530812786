#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the elementary operations of shaders/lib/dual.glsl against the plain float ones.
// In per invocation (24 words): a.v, a.d, b.v, b.d, c, p, -, -, A.v xyz -, A.d xyz -, B.v xyz -,
// B.d xyz - (a > 0 so that sqrt, log and pow are defined; c and p are constants).
// Out per invocation: kDualOpsComponents triples (dual value, dual derivative, plain float value),
// in the order of tests/grad_functions.cpp's opsComponents().
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/dual.glsl"

const uint kDualOpsComponents = 39u;

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
vec3 inV(uint i) { return vec3(inF(i), inF(i + 1u), inF(i + 2u)); }

uint outBase;
uint component;
void put(Dual x, float plain) {
  uint o = outBase + 3u * component;
  testOut[o] = floatBitsToUint(x.v);
  testOut[o + 1u] = floatBitsToUint(x.d);
  testOut[o + 2u] = floatBitsToUint(plain);
  ++component;
}
void put(Dual3 x, vec3 plain) {
  put(Dual(x.v.x, x.d.x), plain.x);
  put(Dual(x.v.y, x.d.y), plain.y);
  put(Dual(x.v.z, x.d.z), plain.z);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint b0 = 24u * i;
  outBase = 3u * kDualOpsComponents * i;
  component = 0u;
  Dual a = dual(inF(b0), inF(b0 + 1u));
  Dual b = dual(inF(b0 + 2u), inF(b0 + 3u));
  float c = inF(b0 + 4u);
  float p = inF(b0 + 5u);
  Dual3 A = dual3(inV(b0 + 8u), inV(b0 + 12u));
  Dual3 B = dual3(inV(b0 + 16u), inV(b0 + 20u));
  put(dAdd(a, b), a.v + b.v);
  put(dSub(a, b), a.v - b.v);
  put(dMul(a, b), a.v * b.v);
  put(dDiv(a, b), a.v / b.v);
  put(dNeg(a), -a.v);
  put(dSqrt(a), sqrt(a.v));
  put(dExp(b), exp(b.v));
  put(dLog(a), log(a.v));
  put(dPow(a, p), pow(a.v, p));
  put(dAbs(b), abs(b.v));
  put(dMax(b, c), max(b.v, c));
  put(dClamp(b, c - 0.5, c + 0.5), clamp(b.v, c - 0.5, c + 0.5));
  put(dMul(a, c), a.v * c);
  put(dDiv(a, c), a.v / c);
  put(dDiv(c, a), c / a.v);
  put(dSub(c, a), c - a.v);
  put(dAdd(a, c), a.v + c);
  put(dDot(A, B), dot(A.v, B.v));
  put(dLength(A), length(A.v));
  put(dDistance(A, B), distance(A.v, B.v));
  put(dCross(A, B), cross(A.v, B.v));
  put(dNormalize(A), normalize(A.v));
  put(dScale(A, a), A.v * a.v);
  put(dScale(A, c), A.v * c);
  put(dAdd(A, B), A.v + B.v);
  put(dSub(A, B), A.v - B.v);
  put(dMin(b, c), min(b.v, c));
}
