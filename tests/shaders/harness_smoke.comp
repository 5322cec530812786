#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: squares its inputs and reports the scene's triangle count (checks the harness itself).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  float x = uintBitsToFloat(testIn[i]);
  testOut[2u * i] = floatBitsToUint(x * x);
  testOut[2u * i + 1u] = frame.sceneCounts.x;
}
