#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: shaders/lib/edge.glsl's edge selection by the fixed-point CDF of the bound edge
// list. In per invocation: 32 random bits u. Out: the selected edge, and where u falls within its
// interval (float bits).
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "test_io.glsl"
#include "lib/edge.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= invocationCount) return;
  uint u = testIn[i];
  uint edge = selectEdge(u);
  testOut[2u * i] = edge;
  testOut[2u * i + 1u] = floatBitsToUint(placeInEdgeInterval(u, edge));
}
