// Double-float arithmetic: a value is the unevaluated sum x + y of a vec2, about 48 significant
// bits from float +, - and * alone (Dekker 1971, Knuth's TwoSum). The GLSL twin of
// include/vktg/double_float.h, operation for operation. Every result is `precise`: the error
// terms are algebraically zero, so a compiler free to contract or reassociate would remove them.
// Exact while nothing overflows (|x| < 1e34) or underflows.
#ifndef VKTG_DOUBLE_FLOAT_GLSL
#define VKTG_DOUBLE_FLOAT_GLSL

// a + b exactly, as the rounded sum and its rounding error.
vec2 twoSum(float a, float b) {
  precise float s = a + b;
  precise float bb = s - a;
  precise float e = (a - (s - bb)) + (b - bb);
  return vec2(s, e);
}

// Requires |a| >= |b| (or a == 0).
vec2 quickTwoSum(float a, float b) {
  precise float s = a + b;
  precise float e = b - (s - a);
  return vec2(s, e);
}

// Veltkamp's split of a float into two 12-bit halves (4097 = 2^12 + 1).
vec2 splitFloat(float a) {
  precise float c = 4097.0 * a;
  precise float hi = c - (c - a);
  precise float lo = a - hi;
  return vec2(hi, lo);
}

// a * b exactly, as the rounded product and its rounding error (Dekker, no FMA needed).
vec2 twoProduct(float a, float b) {
  precise float p = a * b;
  vec2 x = splitFloat(a), y = splitFloat(b);
  precise float err = ((x.x * y.x - p) + x.x * y.y + x.y * y.x) + x.y * y.y;
  return vec2(p, err);
}

vec2 dfAdd(vec2 a, vec2 b) {
  vec2 s = twoSum(a.x, b.x);
  vec2 t = twoSum(a.y, b.y);
  precise float e = s.y + t.x;
  s = quickTwoSum(s.x, e);
  precise float f = s.y + t.y;
  return quickTwoSum(s.x, f);
}

vec2 dfNegate(vec2 a) { return -a; }

vec2 dfMul(vec2 a, vec2 b) {
  vec2 p = twoProduct(a.x, b.x);
  precise float cross = a.x * b.y + a.y * b.x;
  precise float e = p.y + cross;
  return quickTwoSum(p.x, e);
}

// a / b rounded to float: the quotient of the leading parts (any division accuracy), corrected by
// the exact residual, so the result is within about half an ulp of the true quotient.
float dfDivide(vec2 a, vec2 b) {
  precise float q = a.x / b.x;
  vec2 r = dfAdd(a, dfNegate(dfMul(b, vec2(q, 0.0))));
  precise float result = q + r.x / b.x;
  return result;
}
#endif
