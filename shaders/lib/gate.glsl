// Time gates W(L) (THEORY.md §1) and gate sampling for ellipsoidal connections. The gate type is
// a specialisation constant; its numbers come from frame.gate / frame.gateSupport.
// Must match src/scene/gate.cpp (Gate::weight), which tests use as the reference.
#ifndef VKTG_GATE_GLSL
#define VKTG_GATE_GLSL
#include "lib/specialization.glsl"

const float kGaussianCutoff = 6.5;
const float kSqrtTwoPi = 2.50662827463100050242;

// W_k(L) for layer k (k = 0 unless the gate is a stack of bins).
float gateWeight(float len, uint layer) {
  if (kSpecGateTypeValue == kGateSteady) return 1.0;
  if (kSpecGateTypeValue == kGateGaussian) {
    float d = len - frame.gate.x;
    if (abs(d) > kGaussianCutoff * frame.gate.y) return 0.0;
    float z = d / frame.gate.y;
    return exp(-0.5 * z * z) * frame.gateSupport.w;
  }
  if (kSpecGateTypeValue == kGateBox) return (len >= frame.gate.z && len <= frame.gate.w) ? 1.0 : 0.0;
  if (kSpecGateTypeValue == kGateTruncatedGaussian) {
    if (len < frame.gate.z || len > frame.gate.w) return 0.0;
    float z = (len - frame.gate.x) / frame.gate.y;
    return exp(-0.5 * z * z);
  }
  float lo = frame.gate.x + frame.gate.y * float(layer);
  return (len >= lo && len < lo + frame.gate.y) ? 1.0 : 0.0;
}

// The layers whose weight can be non-zero at L: [first, first + count).
void gateLayers(float len, out uint first, out uint count) {
  first = 0u;
  count = 1u;
  if (kSpecGateTypeValue != kGateBins) return;
  float k = floor((len - frame.gate.x) / frame.gate.y);
  if (k < 0.0 || k >= float(frame.gateInfo.y)) { count = 0u; return; }
  first = uint(k);
}

// Whether some layer's W_k(L) can be non-zero (gateWeight's tests negated, so that a NaN length
// still reaches the accumulators, which count it). W_k' vanishes wherever W_k does; the jumps have
// connections of their own. A connection of a length the gate does not reach adds nothing to the
// image or to any derivative, and is not traced.
bool gateReaches(float len) {
  if (kSpecGateTypeValue == kGateGaussian) return !(abs(len - frame.gate.x) > kGaussianCutoff * frame.gate.y);
  if (kSpecGateTypeValue == kGateBox || kSpecGateTypeValue == kGateTruncatedGaussian)
    return !(len < frame.gate.z || len > frame.gate.w);
  uint first, count;  // steady: its one layer; bins: the bin L falls in
  gateLayers(len, first, count);
  return count > 0u;
}

// Draws a total path length s for an ellipsoidal connection and returns 1 / p(s), or 0 when the
// draw falls outside the support (which the estimator then counts as a zero: still unbiased).
// gaussian: normal N(mu, sigma) (W / p is the constant sigma sqrt(2 pi) times the normaliser);
// box, truncated gaussian, bins: uniform over the support.
float gateSampleLength(vec2 u, out float s) {
  if (kSpecGateTypeValue == kGateGaussian) {
    // Box–Muller; 1 - u.x is in (0, 1], so the log is finite.
    float radius = sqrt(-2.0 * log(1.0 - u.x));
    s = frame.gate.x + frame.gate.y * radius * cos(6.28318530717958647692 * u.y);
    float z = (s - frame.gate.x) / frame.gate.y;
    return frame.gate.y * kSqrtTwoPi * exp(0.5 * z * z);
  }
  float lo = frame.gateSupport.x, hi = frame.gateSupport.z;
  s = mix(lo, hi, u.x);
  return hi - lo;
}

// Jumps of W (THEORY.md §3, path-length boundary), in increasing order of length: box and
// truncated gaussian at a and b, bins at every bin edge.
uint gateJumpCount() {
  if (kSpecGateTypeValue == kGateBox || kSpecGateTypeValue == kGateTruncatedGaussian) return 2u;
  if (kSpecGateTypeValue == kGateBins) return frame.gateInfo.y + 1u;
  return 0u;
}

float gateJumpLocation(uint j) {
  if (kSpecGateTypeValue == kGateBins) return frame.gate.x + frame.gate.y * float(j);
  return j == 0u ? frame.gate.z : frame.gate.w;
}

// ΔW_k(s_j) = W_k(s_j+) - W_k(s_j-) for layer k.
float gateJumpSize(uint j, uint layer) {
  if (kSpecGateTypeValue == kGateBins) return layer == j ? 1.0 : (layer + 1u == j ? -1.0 : 0.0);
  float w = 1.0;
  if (kSpecGateTypeValue == kGateTruncatedGaussian) {
    float z = (gateJumpLocation(j) - frame.gate.x) / frame.gate.y;
    w = exp(-0.5 * z * z);
  }
  return j == 0u ? w : -w;
}

// Index of the first jump strictly beyond `len` (gateJumpCount() if none).
uint gateFirstJumpAbove(float len) {
  uint count = gateJumpCount();
  if (kSpecGateTypeValue == kGateBins) {
    float k = floor((len - frame.gate.x) / frame.gate.y) + 1.0;
    return uint(clamp(k, 0.0, float(count)));
  }
  uint j = 0u;
  while (j < count && gateJumpLocation(j) <= len) ++j;
  return j;
}

// The jumps a path-length-boundary sample connects to, among those beyond `reach` (no shorter
// path exists): first, first + 1, ... (the count is returned), each with weight `weight`.
//   plain: one, chosen uniformly (weight: their count);
//   antithetic (two-jump gates, THEORY.md §5): all, sharing every other random number (weight 1).
//     Their ΔW have opposite signs, and for a narrow gate both connections land on nearly the
//     same point, so their large values cancel in the sum.
uint gateBoundaryJumps(float reach, float uJump, out uint first, out float weight) {
  uint count = gateJumpCount();
  first = gateFirstJumpAbove(reach);
  weight = 1.0;
  if (first >= count) return 0u;
  uint choices = count - first;
  if (kSpecAntitheticValue != 0u && count == 2u) return choices;
  first += min(uint(uJump * float(choices)), choices - 1u);
  weight = float(choices);
  return 1u;
}

// The density gateSampleLength draws s from (for MIS weights of other strategies' paths).
float gateSamplePdf(float s) {
  if (kSpecGateTypeValue == kGateGaussian) {
    float z = (s - frame.gate.x) / frame.gate.y;
    return exp(-0.5 * z * z) / (frame.gate.y * kSqrtTwoPi);
  }
  float lo = frame.gateSupport.x, hi = frame.gateSupport.z;
  return (s >= lo && s <= hi) ? 1.0 / (hi - lo) : 0.0;
}
#endif
