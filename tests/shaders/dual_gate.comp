#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the gate derivatives of shaders/lib/geometry_dual.glsl for the gate of the bound
// scene (kSpecGateType), against lib/gate.glsl's gateWeight.
// In per invocation (4 words): L, dL/dθ, layer (uint), centre rate (the gate's shift per unit θ).
// Out per invocation (8 words): 0-1 gateWeightDual(L, layer) value and derivative, 2 gateWeight(L,
// layer), 3 gateCentreDerivative(L, layer), 4 derivative of gateWeightDual(L, layer, rate),
// 5 its value, 6 gateReaches(L) (1 or 0), 7 zero.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/geometry_dual.glsl"

float inF(uint i) { return uintBitsToFloat(testIn[i]); }
void outF(uint i, float v) { testOut[i] = floatBitsToUint(v); }

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint ib = 4u * i;
  uint ob = 8u * i;
  Dual len = dual(inF(ib), inF(ib + 1u));
  uint layer = testIn[ib + 2u];
  float rate = inF(ib + 3u);
  Dual w = gateWeightDual(len, layer);
  Dual shifted = gateWeightDual(len, layer, rate);
  outF(ob, w.v);
  outF(ob + 1u, w.d);
  outF(ob + 2u, gateWeight(len.v, layer));
  outF(ob + 3u, gateCentreDerivative(len.v, layer));
  outF(ob + 4u, shifted.d);
  outF(ob + 5u, shifted.v);
  outF(ob + 6u, gateReaches(len.v) ? 1.0 : 0.0);
  outF(ob + 7u, 0.0);
}
