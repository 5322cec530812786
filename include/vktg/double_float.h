// Double-float arithmetic: a value is the unevaluated sum hi + lo of two floats, which carries
// about 48 significant bits using only float addition, subtraction and multiplication
// (Dekker 1971, Knuth's TwoSum). It is the CPU twin of shaders/lib/double_float.glsl: both round
// the same way because IEEE float +, - and * are correctly rounded on the host and in Vulkan, and
// neither side lets the compiler fuse or reorder them (the GLSL is `precise`; the host is built
// with -ffp-contract=off, see CMakeLists.txt). Exact while nothing overflows (|x| < 1e34) or
// underflows.
#pragma once

namespace vktg {

struct DoubleFloat {
  float hi = 0, lo = 0;
};

// a + b exactly, as the rounded sum and its rounding error.
inline DoubleFloat twoSum(float a, float b) {
  float s = a + b;
  float bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

// Requires |a| >= |b| (or a == 0).
inline DoubleFloat quickTwoSum(float a, float b) {
  float s = a + b;
  return {s, b - (s - a)};
}

// Veltkamp's split of a float into two 12-bit halves (4097 = 2^12 + 1).
inline DoubleFloat splitFloat(float a) {
  float c = 4097.0f * a;
  float hi = c - (c - a);
  return {hi, a - hi};
}

// a * b exactly, as the rounded product and its rounding error (Dekker, no FMA needed).
inline DoubleFloat twoProduct(float a, float b) {
  float p = a * b;
  DoubleFloat x = splitFloat(a), y = splitFloat(b);
  float err = ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo;
  return {p, err};
}

inline DoubleFloat dfAdd(DoubleFloat a, DoubleFloat b) {
  DoubleFloat s = twoSum(a.hi, b.hi);
  DoubleFloat t = twoSum(a.lo, b.lo);
  s = quickTwoSum(s.hi, s.lo + t.hi);
  return quickTwoSum(s.hi, s.lo + t.lo);
}

inline DoubleFloat dfNegate(DoubleFloat a) { return {-a.hi, -a.lo}; }

inline DoubleFloat dfMul(DoubleFloat a, DoubleFloat b) {
  DoubleFloat p = twoProduct(a.hi, b.hi);
  return quickTwoSum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi));
}

// a / b rounded to float: the quotient of the leading parts, corrected by the exact residual, so
// the result is within about half an ulp of the true quotient whatever the division's accuracy.
inline float dfDivide(DoubleFloat a, DoubleFloat b) {
  float q = a.hi / b.hi;
  DoubleFloat r = dfAdd(a, dfNegate(dfMul(b, {q, 0.0f})));
  return q + r.hi / b.hi;
}

}  // namespace vktg
