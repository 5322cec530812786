#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: sampleEllipsoidConnectionStratified against the bound scene, plus
// ellipsoidConnectionDensity at the sample. In (12 words per invocation): f1, f2, s', u (4),
// the stratified number (< 0: none, as sampleEllipsoidConnection). Out (20 words): 0 ok,
// 1 triangle (leaf order), 2-4 position, 5-6 barycentrics, 7 weight, 8 density at the sample,
// 9-17 the chosen triangle's p0, p1, p2 (tests match the triangle by its vertices, independent of
// the BVH order), 18-19 unused.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/ellipsoid.glsl"
layout(local_size_x = 64) in;

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
vec3 inV(uint i) { return vec3(inF(i), inF(i + 1u), inF(i + 2u)); }
void outF(uint i, float v) { testOut[i] = floatBitsToUint(v); }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= invocationCount) return;
  uint ib = id * 12u;
  uint ob = id * 20u;
  vec3 f1 = inV(ib);
  vec3 f2 = inV(ib + 3u);
  float s = inF(ib + 6u);
  vec4 u = vec4(inF(ib + 7u), inF(ib + 8u), inF(ib + 9u), inF(ib + 10u));
  EllipsoidSample es;
  bool ok = sampleEllipsoidConnectionStratified(f1, f2, s, u, inF(ib + 11u), es);
  testOut[ob] = ok ? 1u : 0u;
  testOut[ob + 1u] = es.triangle;
  outF(ob + 2u, es.position.x);
  outF(ob + 3u, es.position.y);
  outF(ob + 4u, es.position.z);
  outF(ob + 5u, es.barycentrics.x);
  outF(ob + 6u, es.barycentrics.y);
  outF(ob + 7u, es.weight);
  outF(ob + 8u, ok ? ellipsoidConnectionDensity(f1, f2, s, es.triangle, es.position) : 0.0);
  for (uint i = 9u; i < 20u; ++i) testOut[ob + i] = 0u;
  if (ok) {
    GpuTriangle tri = loadTriangle(es.triangle);
    for (uint i = 0u; i < 3u; ++i) {
      outF(ob + 9u + i, tri.p0[i]);
      outF(ob + 12u + i, tri.p1[i]);
      outF(ob + 15u + i, tri.p2[i]);
    }
  }
}
