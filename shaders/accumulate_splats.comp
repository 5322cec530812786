#version 460
#extension GL_GOOGLE_include_directive : require
// Pass accumulate_splats: adds a finished batch of splatted samples to the film. A sample owns two
// path slots, and each slot's value lands in whichever pixel its camera connection reached (the
// slot's ids.x), so it is splatted: per (sample, gate layer, lane), with atomics into the film
// element's sum and sum of squares (shift 0). Slots of one sample that reach the same pixel are
// summed before squaring (they are one sample's estimate there). Every sample of the render counts
// in every pixel's mean (a pixel it missed sees a zero), so resolve divides by all samples
// (frame.image.z). A slot's value for a lane:
//   edge term (sample_edges):  the light-side value (pathAccum channel 0) times the lane's factor,
//                              from the slot's EdgeRecord and the lane's velocities (lib/edge.glsl);
//   path-length boundary from the camera (connect_camera_boundary): the lane's channel, where
//                              trace_shadow_rays_d put ΔW f dL/dθ.
// Reads: paths (pixel), pathAccum, edge records, velocities, lanes. Writes: film, kCounterNonFinite.
// Dispatch: ceil(samples * layers * lanes / kWorkgroupSize); push.args.w: samples of the batch.
#define VKTG_LANE_INPUTS 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/specialization.glsl"
#include "lib/edge.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void atomicAddFilm(uint floatIndex, float value) {
  if (kSpecSingleChunkValue != 0u) {
    atomicAdd(film0[floatIndex], value);
    return;
  }
  uint c = floatIndex >> frame.chunkShift.z;
  uint j = floatIndex & ((1u << frame.chunkShift.z) - 1u);
  if (c == 0u) atomicAdd(film0[j], value);
  else if (c == 1u) atomicAdd(film1[j], value);
  else if (c == 2u) atomicAdd(film2[j], value);
  else atomicAdd(film3[j], value);
}

float slotValue(uint slot, uint layer, uint lane) {
  uint layers = frame.gateInfo.y, channels = frame.pathInfo.z;
  if (kSpecTermValue == kTermPathLength) return pathAccum[(slot * layers + layer) * channels + 1u + lane];
  float value = pathAccum[(slot * layers + layer) * channels];
  return value == 0.0 ? 0.0 : value * edgeRecordFactor(edgeRecords[slot], lane);
}

void splat(uint pixel, uint layer, uint lane, float x) {
  if (isnan(x) || isinf(x)) {
    atomicAdd(counters[kCounterNonFinite], 1u);
    return;
  }
  if (pixel == kNoPixel || x == 0.0) return;
  uint element = ((1u + lane) * frame.gateInfo.y + layer) * frame.image.x * frame.image.y + pixel;
  atomicAddFilm(kFilmFloatsPerElement * element + 1u, x);
  atomicAddFilm(kFilmFloatsPerElement * element + 3u, x * x);
}

void main() {
  uint layers = frame.gateInfo.y, laneCount = kSpecLanesValue;
  uint index = gl_GlobalInvocationID.x;
  if (index >= push.args.w * layers * laneCount) return;
  uint i = index / (layers * laneCount);
  setViewOfPath(paths[2u * i]);  // an edge record's factor reads the camera
  uint layer = (index / laneCount) % layers, lane = index % laneCount;
  uint pixel0 = paths[2u * i].ids.x, pixel1 = paths[2u * i + 1u].ids.x;
  float x0 = slotValue(2u * i, layer, lane), x1 = slotValue(2u * i + 1u, layer, lane);
  if (pixel0 == pixel1) {
    splat(pixel0, layer, lane, x0 + x1);
  } else {
    splat(pixel0, layer, lane, x0);
    splat(pixel1, layer, lane, x1);
  }
}
