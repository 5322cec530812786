#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: ellipseOnTriangle and the per-sample quantities for one configuration per
// invocation. In (20 words): f1, f2, s', p0, p1, p2, u, 3 unused. Out (20 words): ok, count,
// total, weight, arcStart[3], arcLength[3], phi, position, barycentrics, speed, ratio, ratioScale.
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
  uint base = id * 20u;
  EllipseArcs arcs;
  bool ok = ellipseOnTriangle(inV(base), inV(base + 3u), inF(base + 6u), inV(base + 7u), inV(base + 10u),
                              inV(base + 13u), arcs);
  testOut[base] = ok ? 1u : 0u;
  testOut[base + 1u] = arcs.count;
  outF(base + 2u, arcs.total);
  outF(base + 3u, arcs.weight);
  for (uint i = 0u; i < 3u; ++i) {
    outF(base + 4u + i, arcs.arcStart[i]);
    outF(base + 7u + i, arcs.arcLength[i]);
  }
  float phi = ok ? ellipseArcPhi(arcs, inF(base + 16u)) : 0.0;
  vec3 x = ok ? ellipsePoint(arcs, phi) : vec3(0.0);
  vec2 bc = ok ? ellipseBarycentrics(arcs, phi) : vec2(0.0);
  outF(base + 10u, phi);
  outF(base + 11u, x.x);
  outF(base + 12u, x.y);
  outF(base + 13u, x.z);
  outF(base + 14u, bc.x);
  outF(base + 15u, bc.y);
  outF(base + 16u, ok ? ellipseSpeed(arcs, phi) : 0.0);
  outF(base + 17u, ok ? ellipseCoareaRatio(arcs, inV(base), inV(base + 3u), x) : 0.0);
  outF(base + 18u, arcs.ratioScale);
  outF(base + 19u, 0.0);
}
