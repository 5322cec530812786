#version 460
#extension GL_GOOGLE_include_directive : require
// Pass accumulate: adds a finished batch to the film. One invocation per film element (channel,
// layer, pixel) sums, in batch order, the values of the batch's paths of that pixel (they sit at a
// stride of `pixels` in the batch) with Kahan compensation and a per-element shift, so no
// precision is lost to atomics in arbitrary order or to E[x^2] - E[x]^2 cancellation.
// Each dispatch (a round) takes at most kPathsPerRound paths per element: some drivers cap loop
// iterations (llvmpipe at 65535), and rounds keep every invocation short.
// Reads: pathAccum, push.args (x: first pixel-sample index of the batch, y: round, z: batch index,
// w: active paths). Writes: film. Dispatch: ceil(film elements / kWorkgroupSize) groups per round.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/path.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
  uint pixels = frame.image.x * frame.image.y;
  uint e = gl_GlobalInvocationID.x;
  if (e >= pixels * layers * channels) return;
  uint pixel = e % pixels;
  uint layer = (e / pixels) % layers;
  uint channel = e / (pixels * layers);
  uint activePaths = push.args.w;
  // Path i of the batch renders pixel (first + i) % pixels; this round starts kPathsPerRound
  // of this pixel's paths further on.
  uint i = (pixel + pixels - push.args.x % pixels) % pixels + push.args.y * kPathsPerRound * pixels;
  if (i >= activePaths) return;
  bool first = push.args.z == 0u && push.args.y == 0u;
  vec4 f = first ? vec4(pathAccum[(i * layers + layer) * channels + channel], 0.0, 0.0, 0.0) : loadFilm(e);
  // The squares are summed plainly, in sample order: the film has no room to carry their
  // compensation from one batch to the next, and a compensation restarted at every batch would
  // make the variance's last bits depend on the batch size. Their sum has no cancellation (all
  // terms are >= 0), so its relative rounding error stays far below the variance's own
  // statistical error.
  float sum = f.y, compensation = f.z, squares = f.w;
  for (uint k = 0u; k < kPathsPerRound && i < activePaths; ++k, i += pixels) {
    float d = pathAccum[(i * layers + layer) * channels + channel] - f.x;
    addLength(sum, compensation, d);
    squares += d * d;
  }
  storeFilm(e, vec4(f.x, sum, compensation, squares));
}
