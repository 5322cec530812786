#version 460
#extension GL_GOOGLE_include_directive : require
// Pass accumulate: adds each finished path's per-layer value (and its square, for the
// per-pixel variance) to the film.
// Reads: pathAccum, paths[].ids.x (pixel). Writes: film sums and sums of squares (atomic:
// paths share pixels).
// Dispatch: ceil(active paths * layers * channels / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  // One invocation per (path, layer, channel); channel 0 is the image, 1..K derivative lanes.
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w * layers * channels) return;
  uint channel = i % channels;
  uint pathLayer = i / channels;
  uint path = pathLayer / layers, layer = pathLayer % layers;
  float value = pathAccum[i];
  uint pixels = frame.image.x * frame.image.y;
  addToFilm((channel * layers + layer) * pixels + paths[path].ids.x, value);
}
