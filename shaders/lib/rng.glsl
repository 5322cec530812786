// Counter-based random numbers: every value is a hash of (pixel, sample, dimension, seed), so a
// render is reproducible from its seed and finite differences can share random numbers.
#ifndef VKTG_RNG_GLSL
#define VKTG_RNG_GLSL

// PCG-style 4D hash (Jarzynski & Olano 2020 construction): 4 x 32-bit in, 4 x 32-bit out.
uvec4 hash4(uvec4 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  v ^= v >> 16u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  return v;
}

// Maps 32 random bits to [0, 1) with 24 bits of precision (never returns 1).
float bitsToUnit(uint bits) { return float(bits >> 8u) * (1.0 / 16777216.0); }

// Random stream of one path: `dimension` advances as the path consumes numbers.
struct Rng {
  uvec4 key;  // pixel, sample, dimension, seed
};

Rng rngCreate(uint pixel, uint sampleIndex, uint dimension, uint seed) {
  Rng r;
  r.key = uvec4(pixel, sampleIndex, dimension, seed);
  return r;
}

// Four 32-bit random words from the current dimension, then advances it.
uvec4 rngNextBits4(inout Rng r) {
  uvec4 h = hash4(r.key);
  r.key.z += 1u;
  return h;
}

// Four uniforms from the current dimension, then advances it.
vec4 rngNext4(inout Rng r) {
  uvec4 h = rngNextBits4(r);
  return vec4(bitsToUnit(h.x), bitsToUnit(h.y), bitsToUnit(h.z), bitsToUnit(h.w));
}

// Fixed dimension layout per path vertex, so that common random numbers line up between renders
// of perturbed scenes: the numbers of bounce d are dimension kRngDimBounceBase + d * kRngDimsPerBounce + slot.
const uint kRngDimCamera = 0u;      // pixel jitter, gate sample, lens
const uint kRngDimBounceBase = 4u;
// Slots of a bounce: 0 BSDF sample, 1 standard-NEE light + roulette, 2 ellipsoid point,
// 3 gate length (xy), 4 light of the ellipsoidal connection.
const uint kRngDimsPerBounce = 5u;
const uint kRngSlotBsdf = 0u;
const uint kRngSlotLight = 1u;
const uint kRngSlotEllipsoid = 2u;
const uint kRngSlotGate = 3u;
const uint kRngSlotEllipsoidLight = 4u;

Rng rngForBounce(uint pixel, uint sampleIndex, uint depth, uint slot, uint seed) {
  return rngCreate(pixel, sampleIndex, kRngDimBounceBase + depth * kRngDimsPerBounce + slot, seed);
}

// One random number per render and `dimension`, the same for all its samples: the stream of
// pixel ~0 and sample ~1, which no sample has.
uint renderBits(uint dimension, uint seed) { return hash4(uvec4(0xffffffffu, 0xfffffffeu, dimension, seed)).x; }

// Point `index` of a golden-ratio (Kronecker) sequence shifted at random: each point alone is
// uniform on [0, 1) (the shift is), and any n consecutive points lie about 1/n apart, so an
// estimate that sums the samples of one stream stratifies this dimension (randomised quasi-Monte
// Carlo: unbiased, with the variance of a stratified estimate).
uint stratifiedBits(uint index, uint dimension, uint seed) {
  return renderBits(dimension, seed) + index * 2654435769u;  // 2^32 (sqrt(5) - 1) / 2
}

float stratifiedUnit(uint index, uint dimension, uint seed) { return bitsToUnit(stratifiedBits(index, dimension, seed)); }
#endif
