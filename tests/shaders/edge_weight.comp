#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: shaders/lib/edge.glsl's silhouette plane and normal velocity v_n (minus the factor of
// a boundary record), the pieces of the edge-sample weight. In per invocation (EdgeWeightIn in tests/gpu_edge.cpp): edge ends a0, a1,
// face directions inward0, inward1, their end velocities u0, u1, the edge parameter t, the unit
// direction w, distances dA, dB of x_a = y - dA w and x_b = y + dB w, and the velocities vA, vB.
// Out: silhouette (1/0), n_p (3), sin(phi), v_n.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/edge.glsl"

const uint kInWords = 32u, kOutWords = 6u;

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
vec3 inV(uint i) { return vec3(inF(i), inF(i + 1u), inF(i + 2u)); }

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint b = kInWords * i;
  GpuEdge e;
  e.p0 = vec4(inV(b), 0.0);
  e.p1 = vec4(inV(b + 3u), 0.0);
  e.inward0 = vec4(inV(b + 6u), 0.0);
  e.inward1 = vec4(inV(b + 9u), 0.0);
  vec3 u0 = inV(b + 12u), u1 = inV(b + 15u);
  float t = inF(b + 18u);
  vec3 w = inV(b + 19u);
  float dA = inF(b + 22u), dB = inF(b + 23u);
  vec3 vA = inV(b + 24u), vB = inV(b + 27u);
  vec3 np;
  float sinPhi;
  bool silhouette = silhouettePlane(e, w, np, sinPhi);
  float vn = -recordFactor(boundaryRecord(0u, t, np, dA, dB), mix(u0, u1, t), vA, vB);
  uint o = kOutWords * i;
  testOut[o] = silhouette ? 1u : 0u;
  testOut[o + 1u] = floatBitsToUint(np.x);
  testOut[o + 2u] = floatBitsToUint(np.y);
  testOut[o + 3u] = floatBitsToUint(np.z);
  testOut[o + 4u] = floatBitsToUint(sinPhi);
  testOut[o + 5u] = floatBitsToUint(vn);
}
