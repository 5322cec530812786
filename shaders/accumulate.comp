#version 460
#extension GL_GOOGLE_include_directive : require
// Pass accumulate: adds each finished path's per-layer value (and its square, for the
// per-pixel variance) to the film.
// Reads: pathAccum, paths[].ids.x (pixel). Writes: film sums and sums of squares (atomic:
// paths share pixels).
// Dispatch: ceil(active paths * layers / kWorkgroupSize) groups.
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint layers = frame.gateInfo.y;
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.args.w * layers) return;
  uint path = i / layers, layer = i % layers;
  float value = pathAccum[i];
  uint pixels = frame.image.x * frame.image.y;
  addToFilm(layer * pixels + paths[path].ids.x, value);
}
