// Time gates W(L) (THEORY.md §1) and gate sampling for ellipsoidal connections. The gate type is
// a specialisation constant; its numbers come from frame.gate / gateSupportNumbers().
// Must match src/scene/gate.cpp (Gate::weight), which tests use as the reference.
#ifndef VKTG_GATE_GLSL
#define VKTG_GATE_GLSL
#include "lib/specialization.glsl"
#include "lib/view.glsl"

const float kGaussianCutoff = 6.5;

// The gate as the current view's paths meet it. A view may count optical path outside the scene
// (viewPathOffset: a capture device's legs to and from the relay wall); W applied to L plus that
// offset is W with every location (centre, ends, bin start, support) moved back by it, so the
// shaders compare the scene's own path lengths with these numbers. Widths and the normaliser stay.
vec4 gateNumbers() {
  float o = viewPathOffset();
  return frame.gate - (kSpecGateTypeValue == kGateBins ? vec4(o, 0.0, 0.0, 0.0) : vec4(o, 0.0, o, o));
}
vec4 gateSupportNumbers() { return frame.gateSupport - vec4(vec3(viewPathOffset()), 0.0); }
const float kSqrtTwoPi = 2.50662827463100050242;

// W_k(L) for layer k (k = 0 unless the gate is a stack of bins).
float gateWeight(float len, uint layer) {
  if (kSpecGateTypeValue == kGateSteady) return 1.0;
  if (kSpecGateTypeValue == kGateGaussian) {
    float d = len - gateNumbers().x;
    if (abs(d) > kGaussianCutoff * gateNumbers().y) return 0.0;
    float z = d / gateNumbers().y;
    return exp(-0.5 * z * z) * gateSupportNumbers().w;
  }
  if (kSpecGateTypeValue == kGateBox) return (len >= gateNumbers().z && len <= gateNumbers().w) ? 1.0 : 0.0;
  if (kSpecGateTypeValue == kGateTruncatedGaussian) {
    if (len < gateNumbers().z || len > gateNumbers().w) return 0.0;
    float z = (len - gateNumbers().x) / gateNumbers().y;
    return exp(-0.5 * z * z);
  }
  float lo = gateNumbers().x + gateNumbers().y * float(layer);
  return (len >= lo && len < lo + gateNumbers().y) ? 1.0 : 0.0;
}

// The layers whose weight can be non-zero at L: [first, first + count).
void gateLayers(float len, out uint first, out uint count) {
  first = 0u;
  count = 1u;
  if (kSpecGateTypeValue != kGateBins) return;
  float k = floor((len - gateNumbers().x) / gateNumbers().y);
  if (k < 0.0 || k >= float(frame.gateInfo.y)) { count = 0u; return; }
  first = uint(k);
}

// Whether some layer's W_k(L) can be non-zero (gateWeight's tests negated, so that a NaN length
// still reaches the accumulators, which count it). W_k' vanishes wherever W_k does; the jumps have
// connections of their own. A connection of a length the gate does not reach adds nothing to the
// image or to any derivative, and is not traced.
bool gateReaches(float len) {
  if (kSpecGateTypeValue == kGateGaussian) return !(abs(len - gateNumbers().x) > kGaussianCutoff * gateNumbers().y);
  if (kSpecGateTypeValue == kGateBox || kSpecGateTypeValue == kGateTruncatedGaussian)
    return !(len < gateNumbers().z || len > gateNumbers().w);
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
    s = gateNumbers().x + gateNumbers().y * radius * cos(6.28318530717958647692 * u.y);
    float z = (s - gateNumbers().x) / gateNumbers().y;
    return gateNumbers().y * kSqrtTwoPi * exp(0.5 * z * z);
  }
  float lo = gateSupportNumbers().x, hi = gateSupportNumbers().z;
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
  if (kSpecGateTypeValue == kGateBins) return gateNumbers().x + gateNumbers().y * float(j);
  return j == 0u ? gateNumbers().z : gateNumbers().w;
}

// ΔW_k(s_j) = W_k(s_j+) - W_k(s_j-) for layer k.
float gateJumpSize(uint j, uint layer) {
  if (kSpecGateTypeValue == kGateBins) return layer == j ? 1.0 : (layer + 1u == j ? -1.0 : 0.0);
  float w = 1.0;
  if (kSpecGateTypeValue == kGateTruncatedGaussian) {
    float z = (gateJumpLocation(j) - gateNumbers().x) / gateNumbers().y;
    w = exp(-0.5 * z * z);
  }
  return j == 0u ? w : -w;
}

// Index of the first jump strictly beyond `len` (gateJumpCount() if none).
uint gateFirstJumpAbove(float len) {
  uint count = gateJumpCount();
  if (kSpecGateTypeValue == kGateBins) {
    float k = floor((len - gateNumbers().x) / gateNumbers().y) + 1.0;
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
    float z = (s - gateNumbers().x) / gateNumbers().y;
    return exp(-0.5 * z * z) / (gateNumbers().y * kSqrtTwoPi);
  }
  float lo = gateSupportNumbers().x, hi = gateSupportNumbers().z;
  return (s >= lo && s <= hi) ? 1.0 / (hi - lo) : 0.0;
}
#endif
