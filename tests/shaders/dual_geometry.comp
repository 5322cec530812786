#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: shaders/lib/geometry_dual.glsl (segments, triangle normal and area, area Jacobian,
// |cos|, ray-form hit) against the plain float computations.
// In per invocation (32 words): p0, p1, p2 (9), their velocities (9), q and its velocity (6),
// ray origin o (3), unit ray direction w (3), barycentrics uv (2) of the ray's hit.
// Out per invocation: 14 triples (dual value, dual derivative, plain value): 0 |q - p0|,
// 1-3 direction p0 -> q, 4-6 triangle normal, 7 area, 8 area Jacobian (plain: 1), 9 |n . dir|,
// 10-12 ray hit (plain: the barycentric surface point), 13 ray hit distance (plain |x - o|).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/geometry_dual.glsl"

const uint kComponents = 14u;

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
  uint b0 = 32u * i;
  outBase = 3u * kComponents * i;
  component = 0u;
  Dual3 p0 = dual3(inV(b0), inV(b0 + 9u));
  Dual3 p1 = dual3(inV(b0 + 3u), inV(b0 + 12u));
  Dual3 p2 = dual3(inV(b0 + 6u), inV(b0 + 15u));
  Dual3 q = dual3(inV(b0 + 18u), inV(b0 + 21u));
  vec3 o = inV(b0 + 24u);
  vec3 w = inV(b0 + 27u);
  vec2 uv = vec2(inF(b0 + 30u), inF(b0 + 31u));

  DualSegment s = dualSegment(p0, q);
  put(s.len, length(q.v - p0.v));
  put(s.dir, normalize(q.v - p0.v));
  Dual3 n = triangleNormalDual(p0, p1, p2);
  vec3 c = cross(p1.v - p0.v, p2.v - p0.v);
  put(n, normalize(c));
  put(triangleAreaDual(p0, p1, p2), length(c) * 0.5);
  put(areaJacobianDual(p0, p1, p2), 1.0);
  put(dAbsCos(n, s.dir), abs(dot(normalize(c), normalize(q.v - p0.v))));
  vec3 x = (1.0 - uv.x - uv.y) * p0.v + uv.x * p1.v + uv.y * p2.v;
  put(rayHitDual(w, p0, p1, p2, uv), x);
  put(rayHitDistanceDual(o, w, p0, p1, p2, uv), distance(o, x));
}
