#version 460
#extension GL_GOOGLE_include_directive : require
// Pass resolve: turns film sums into the per-pixel mean and the variance of that mean
// ((E[x^2] - E[x]^2) / (n - 1)), in place.
// Reads/writes: film, filmSq. Dispatch: ceil(pixels * layers / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void storeFilm(uint i, float mean, float variance) {
  uint c = i >> frame.chunkShift.z;
  uint j = i & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) { film0[j] = mean; filmSq0[j] = variance; }
  else if (c == 1u) { film1[j] = mean; filmSq1[j] = variance; }
  else if (c == 2u) { film2[j] = mean; filmSq2[j] = variance; }
  else { film3[j] = mean; filmSq3[j] = variance; }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  float n = float(frame.image.z);
  float mean = loadFilm(i) / n;
  float meanSq = loadFilmSq(i) / n;
  float variance = n > 1.0 ? max(meanSq - mean * mean, 0.0) / (n - 1.0) : 0.0;
  storeFilm(i, mean, variance);
}
