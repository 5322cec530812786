// Forward-mode dual numbers with ONE tangent (THEORY.md §2-3). GLSL cannot assign or return arrays
// sized by specialisation constants, so derivative passes loop over their K lanes and run each lane
// with these plain, assignable structs: v is the value, d = dv/dθ for the lane's parameter θ.
//
// Naming: every operation is `d` + the operation (dAdd, dSub, dMul, dDiv, dNeg, dSqrt, dExp, dLog,
// dPow, dAbs, dMax, dClamp, dDot, dCross, dLength, dNormalize, dScale, dDistance), overloaded on
// Dual / Dual3 / float operands; a float operand is a constant (zero derivative). Constructors are
// dual(v), dual(v, d), dual3(v), dual3(v, d).
//
// Value parts are computed with exactly the operations the plain float code uses (normalize,
// length, sqrt...), so a dual function's value is the non-dual function's value.
// Non-differentiable points get a one-sided convention, stated at each function: abs and max take
// the derivative of the branch the value takes (ties: the first operand); clamp's derivative is 0
// when the value is clamped; sqrt and length have an infinite derivative at 0 (callers avoid it).
#ifndef VKTG_DUAL_GLSL
#define VKTG_DUAL_GLSL

struct Dual {
  float v;
  float d;
};

struct Dual3 {
  vec3 v;
  vec3 d;
};

Dual dual(float v) { return Dual(v, 0.0); }
Dual dual(float v, float d) { return Dual(v, d); }
Dual3 dual3(vec3 v) { return Dual3(v, vec3(0.0)); }
Dual3 dual3(vec3 v, vec3 d) { return Dual3(v, d); }

// Components of a Dual3 as Duals, and a Dual3 from three Duals.
Dual dX(Dual3 a) { return Dual(a.v.x, a.d.x); }
Dual dY(Dual3 a) { return Dual(a.v.y, a.d.y); }
Dual dZ(Dual3 a) { return Dual(a.v.z, a.d.z); }
Dual3 dual3(Dual x, Dual y, Dual z) { return Dual3(vec3(x.v, y.v, z.v), vec3(x.d, y.d, z.d)); }

// ---- Scalars ------------------------------------------------------------------------------------
Dual dAdd(Dual a, Dual b) { return Dual(a.v + b.v, a.d + b.d); }
Dual dAdd(Dual a, float b) { return Dual(a.v + b, a.d); }
Dual dAdd(float a, Dual b) { return Dual(a + b.v, b.d); }
Dual dSub(Dual a, Dual b) { return Dual(a.v - b.v, a.d - b.d); }
Dual dSub(Dual a, float b) { return Dual(a.v - b, a.d); }
Dual dSub(float a, Dual b) { return Dual(a - b.v, -b.d); }
Dual dMul(Dual a, Dual b) { return Dual(a.v * b.v, a.d * b.v + a.v * b.d); }
Dual dMul(Dual a, float b) { return Dual(a.v * b, a.d * b); }
Dual dMul(float a, Dual b) { return Dual(a * b.v, a * b.d); }
// (a/b)' = (a' b - a b') / b^2 = (a' - (a/b) b') / b: reuses the quotient, one division less.
Dual dDiv(Dual a, Dual b) {
  float q = a.v / b.v;
  return Dual(q, (a.d - q * b.d) / b.v);
}
Dual dDiv(Dual a, float b) { return Dual(a.v / b, a.d / b); }
Dual dDiv(float a, Dual b) {
  float q = a / b.v;
  return Dual(q, -q * b.d / b.v);
}
Dual dNeg(Dual a) { return Dual(-a.v, -a.d); }
Dual dSqrt(Dual a) {
  float s = sqrt(a.v);
  return Dual(s, a.d / (2.0 * s));
}
Dual dExp(Dual a) {
  float e = exp(a.v);
  return Dual(e, e * a.d);
}
Dual dLog(Dual a) { return Dual(log(a.v), a.d / a.v); }
// a^p for a constant exponent, a > 0 (p a^(p-1) a' written as p (a^p / a) a').
Dual dPow(Dual a, float p) {
  float r = pow(a.v, p);
  return Dual(r, p * r / a.v * a.d);
}
// The derivative of the branch taken; at a = 0 that of +a.
Dual dAbs(Dual a) { return a.v >= 0.0 ? a : Dual(-a.v, -a.d); }
// max(a, c) for a constant c: the derivative of a where a wins (ties included), else 0.
Dual dMax(Dual a, float c) { return a.v >= c ? a : Dual(c, 0.0); }
Dual dMin(Dual a, float c) { return a.v <= c ? a : Dual(c, 0.0); }
// Clamped values have derivative 0; values on the bounds keep a's derivative.
Dual dClamp(Dual a, float lo, float hi) {
  if (a.v < lo) return Dual(lo, 0.0);
  if (a.v > hi) return Dual(hi, 0.0);
  return a;
}

// ---- Vectors ------------------------------------------------------------------------------------
Dual3 dAdd(Dual3 a, Dual3 b) { return Dual3(a.v + b.v, a.d + b.d); }
Dual3 dAdd(Dual3 a, vec3 b) { return Dual3(a.v + b, a.d); }
Dual3 dSub(Dual3 a, Dual3 b) { return Dual3(a.v - b.v, a.d - b.d); }
Dual3 dSub(Dual3 a, vec3 b) { return Dual3(a.v - b, a.d); }
Dual3 dSub(vec3 a, Dual3 b) { return Dual3(a - b.v, -b.d); }
Dual3 dNeg(Dual3 a) { return Dual3(-a.v, -a.d); }
Dual3 dScale(Dual3 a, Dual s) { return Dual3(a.v * s.v, a.d * s.v + a.v * s.d); }
Dual3 dScale(Dual3 a, float s) { return Dual3(a.v * s, a.d * s); }
Dual3 dScale(vec3 a, Dual s) { return Dual3(a * s.v, a * s.d); }
Dual dDot(Dual3 a, Dual3 b) { return Dual(dot(a.v, b.v), dot(a.d, b.v) + dot(a.v, b.d)); }
Dual dDot(Dual3 a, vec3 b) { return Dual(dot(a.v, b), dot(a.d, b)); }
Dual3 dCross(Dual3 a, Dual3 b) { return Dual3(cross(a.v, b.v), cross(a.d, b.v) + cross(a.v, b.d)); }
// |a|' = (a . a') / |a|; infinite at a = 0.
Dual dLength(Dual3 a) {
  float l = length(a.v);
  return Dual(l, dot(a.v, a.d) / l);
}
// (a / |a|)' = (a' - u (u . a')) / |a| with u = a / |a|: the part of a' across u, over the length.
Dual3 dNormalize(Dual3 a) {
  vec3 u = normalize(a.v);
  float l = length(a.v);
  return Dual3(u, (a.d - u * dot(u, a.d)) / l);
}
Dual dDistance(Dual3 a, Dual3 b) { return dLength(dSub(a, b)); }
#endif
