#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: sampleLight (shaders/lib/lights.glsl) against the bound scene's lights.
// In (4 words per invocation): u.x (light selection), u.y, u.z (point on the triangle), unused.
// Out (12 words): 0 ok (uint), 1 isPoint (uint), 2-4 position, 5-7 normal, 8 emission, 9 pdf,
// 10-11 zero.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/lights.glsl"

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
void outF(uint i, float v) { testOut[i] = floatBitsToUint(v); }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= invocationCount) return;
  uint ib = id * 4u;
  uint ob = id * 12u;
  LightSample ls;
  bool ok = sampleLight(vec3(inF(ib), inF(ib + 1u), inF(ib + 2u)), ls);
  testOut[ob] = ok ? 1u : 0u;
  testOut[ob + 1u] = ls.isPoint ? 1u : 0u;
  outF(ob + 2u, ls.position.x);
  outF(ob + 3u, ls.position.y);
  outF(ob + 4u, ls.position.z);
  outF(ob + 5u, ls.normal.x);
  outF(ob + 6u, ls.normal.y);
  outF(ob + 7u, ls.normal.z);
  outF(ob + 8u, ls.emission);
  outF(ob + 9u, ls.pdf);
  testOut[ob + 10u] = 0u;
  testOut[ob + 11u] = 0u;
}
