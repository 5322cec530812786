#version 460
#extension GL_GOOGLE_include_directive : require
// Pass accumulate_edges: adds a finished batch of edge samples (sample_edges) to the film. An
// edge sample lands in whichever pixel its camera connection reached, so its value is splatted:
// per (sample, gate layer, lane) the sum over the sample's two slots of the slot's light-side
// value (pathAccum channel 0) times its lane factor, added with atomics to the film element's sum
// and sum of squares (shift 0). Every sample of the render counts in every pixel's mean (a pixel
// it missed sees a zero), so resolve divides by all edge samples (frame.image.z).
// Reads: paths (pixel), pathAccum, pathDerivs (factors). Writes: film, kCounterNonFinite.
// Dispatch: ceil(samples * layers * lanes / kWorkgroupSize); push.args.w: samples of the batch.
#define VKTG_DERIVATIVE 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/specialization.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void atomicAddFilm(uint floatIndex, float value) {
  uint c = floatIndex >> frame.chunkShift.z;
  uint j = floatIndex & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) atomicAdd(film0[j], value);
  else if (c == 1u) atomicAdd(film1[j], value);
  else if (c == 2u) atomicAdd(film2[j], value);
  else atomicAdd(film3[j], value);
}

void main() {
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z, lanes = kSpecLanesValue;
  uint index = gl_GlobalInvocationID.x;
  if (index >= push.args.w * layers * lanes) return;
  uint i = index / (layers * lanes);
  uint layer = (index / lanes) % layers, lane = index % lanes;
  uint pixel = paths[2u * i].ids.x;
  if (pixel == kNoPixel) pixel = paths[2u * i + 1u].ids.x;
  if (pixel == kNoPixel) return;
  float x = 0.0;
  for (uint side = 0u; side < 2u; ++side) {
    uint slot = 2u * i + side;
    x += pathAccum[(slot * layers + layer) * channels] * pathDerivs[slot * lanes + lane].positionThroughput.x;
  }
  if (isnan(x) || isinf(x)) {
    atomicAdd(counters[kCounterNonFinite], 1u);
    return;
  }
  if (x == 0.0) return;
  uint pixels = frame.image.x * frame.image.y;
  uint element = ((1u + lane) * layers + layer) * pixels + pixel;
  atomicAddFilm(kFilmFloatsPerElement * element + 1u, x);
  atomicAddFilm(kFilmFloatsPerElement * element + 3u, x * x);
}
