#version 460
#extension GL_GOOGLE_include_directive : require
// Pass resolve: turns film sums into the per-pixel mean and the variance of that mean
// ((E[x^2] - E[x]^2) / (n - 1)), in place.
// Reads/writes: film (sum, sum of squares) -> (mean, variance of the mean). Dispatch: ceil(pixels * layers / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  float n = float(frame.image.z);
  vec2 sums = loadFilm(i);
  float mean = sums.x / n;
  float meanSq = sums.y / n;
  float variance = n > 1.0 ? max(meanSq - mean * mean, 0.0) / (n - 1.0) : 0.0;
  storeFilm(i, vec2(mean, variance));
}
