#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: gateSampleLength, gateWeight and gateLayers (shaders/lib/gate.glsl) for the gate of
// the bound scene (its type is the kSpecGateType specialisation constant).
// In (4 words per invocation): u.x, u.y, a length L, a layer k (uint).
// Out (8 words): 0 s = the sampled length, 1 the returned 1 / p(s), 2 the sum over the layers that
// gateLayers(s) names of gateWeight(s, layer), 3 gateWeight(L, k), 4-5 gateLayers(L) first and
// count (uint), 6-7 zero.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/gate.glsl"

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
void outF(uint i, float v) { testOut[i] = floatBitsToUint(v); }

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= invocationCount) return;
  uint ib = id * 4u;
  uint ob = id * 8u;
  float s;
  float invPdf = gateSampleLength(vec2(inF(ib), inF(ib + 1u)), s);
  uint first, count;
  gateLayers(s, first, count);
  float total = 0.0;
  for (uint k = first; k < first + count; ++k) total += gateWeight(s, k);
  outF(ob, s);
  outF(ob + 1u, invPdf);
  outF(ob + 2u, total);
  float len = inF(ib + 2u);
  outF(ob + 3u, gateWeight(len, testIn[ib + 3u]));
  gateLayers(len, first, count);
  testOut[ob + 4u] = first;
  testOut[ob + 5u] = count;
  testOut[ob + 6u] = 0u;
  testOut[ob + 7u] = 0u;
}
