#version 460
#extension GL_GOOGLE_include_directive : require
// Pass move_vertices (scene update): every vertex some optimised parameter moves is recomputed from
// its position at θ = 0 by applying its parameters' motions in the order the scene declares them
// (ParameterModel, the host's double-precision twin): translate and displace add θ times the axis,
// rotate turns about the axis through the centre by θ radians.
// Reads: basePositions, vertexOps, opList, parameterOps, theta. Writes: vertices.
// Dispatch: ceil(vertices / kWorkgroupSize).
#include "lib/common.glsl"
#include "lib/update_bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;

// Rodrigues' formula, as the host's rotateAbout.
vec3 rotateAbout(vec3 p, vec3 axis, vec3 center, float angle) {
  vec3 r = p - center;
  float c = cos(angle), s = sin(angle);
  return center + r * c + cross(axis, r) * s + axis * (dot(axis, r) * (1.0 - c));
}

void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= floatBitsToUint(frame.sceneInfo.w)) return;
  uvec2 ops = vertexOps[v];
  if (ops.y == 0u) return;  // never moves: keeps its position at θ = 0
  vec3 p = basePositions[v].xyz;
  for (uint o = ops.x; o < ops.x + ops.y; ++o) {
    uint k = opList[o];
    GpuParameterOp op = parameterOps[k];
    if (floatBitsToUint(op.axisKind.w) == kParameterRotate) p = rotateAbout(p, op.axisKind.xyz, op.center.xyz, theta[k]);
    else p += op.axisKind.xyz * theta[k];
  }
  vertices[v] = vec4(p, 1.0);
}
