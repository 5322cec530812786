#version 460
#extension GL_GOOGLE_include_directive : require
// Pass resolve: turns each film element's shifted sums into the mean and the variance of the
// mean: with d = x - K, mean = K + sum(d) / n, variance = (sum(d^2) - sum(d)^2 / n) / (n (n - 1)).
// Reads/writes: film (x <- mean, y <- variance of the mean). Dispatch: ceil(elements / kWorkgroupSize).
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w) return;
  float n = float(frame.image.z);
  vec4 f = loadFilm(i);
  float sum = f.y - f.z;  // Kahan: z holds the rounding error still to subtract
  float mean = f.x + sum / n;
  float variance = n > 1.0 ? max(f.w - sum * sum / n, 0.0) / (n * (n - 1.0)) : 0.0;
  storeFilm(i, vec4(mean, variance, 0.0, 0.0));
}
