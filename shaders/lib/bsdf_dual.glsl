// bsdfEval of lib/bsdf.glsl with one derivative lane (lib/dual.glsl): the same function, branch for
// branch (two-sided flip, kBsdfMinCos cut-offs, roughness clamp, total internal reflection, the
// refraction validity tests), with derivatives through the directions, the normal and the
// material scalars. Requires lib/common.glsl and GpuMaterial (vktg/gpu/shared.h) first.
//
//   Dual bsdfEvalDual(GpuMaterial m, Dual albedo, Dual roughness, Dual ior, Dual3 n, Dual3 wi, Dual3 wo)
//       m.type selects the material; its scalars come from albedo, roughness and ior (so a lane can
//       differentiate with respect to them; pass dual(m.albedo) etc. for constants). Its value is
//       bsdfEval(m, n, wi, wo) for m with those scalars, computed with the same operations.
//       n, wi and wo are unit vectors whose derivatives are perpendicular to them (dNormalize's
//       output is), as bsdfEval assumes unit inputs.
//
// The local frame. bsdfEval works in the frame (t, b, n) of basisFromNormal. f is invariant under
// rotations of (t, b) about n, so any differentiable frame that agrees at θ0 gives the same
// derivative; the one used here is parallel transport: t' = -(t . n') n, b' = -(b . n') n, which keeps
// the frame orthonormal to first order, and avoids differentiating basisFromNormal (discontinuous at
// n.z = 0). The value uses basisFromNormal itself, so it matches bsdfEval's local coordinates.
#ifndef VKTG_BSDF_DUAL_GLSL
#define VKTG_BSDF_DUAL_GLSL
#include "lib/bsdf.glsl"
#include "lib/dual.glsl"

struct BsdfFrameDual {
  vec3 t;
  vec3 b;
  vec3 tRate;
  vec3 bRate;
  Dual3 n;
};

BsdfFrameDual bsdfFrameDual(Dual3 n, Dual3 wi) {
  BsdfFrameDual f;
  f.n = dot(n.v, wi.v) >= 0.0 ? n : dNeg(n);
  basisFromNormal(f.n.v, f.t, f.b);
  f.tRate = -dot(f.t, f.n.d) * f.n.v;
  f.bRate = -dot(f.b, f.n.d) * f.n.v;
  return f;
}

Dual3 toLocalDual(BsdfFrameDual f, Dual3 w) {
  return Dual3(vec3(dot(w.v, f.t), dot(w.v, f.b), dot(w.v, f.n.v)),
               vec3(dot(w.d, f.t) + dot(w.v, f.tRate), dot(w.d, f.b) + dot(w.v, f.bRate),
                    dot(w.d, f.n.v) + dot(w.v, f.n.d)));
}

// ---- Microfacet pieces (lib/microfacet.glsl), same operations in the same order ---------------

Dual ggxDDual(Dual3 h, Dual alpha) {
  Dual a2 = dMul(alpha, alpha);
  Dual hx = dX(h), hy = dY(h), hz = dZ(h);
  Dual k = dAdd(dDiv(dAdd(dMul(hx, hx), dMul(hy, hy)), a2), dMul(hz, hz));
  return dDiv(1.0, dMul(dMul(dMul(kPi, a2), k), k));
}

Dual smithLambdaDual(Dual3 w, Dual alpha) {
  Dual wx = dX(w), wy = dY(w), wz = dZ(w);
  Dual z2 = dMul(wz, wz);
  Dual s2 = dAdd(dMul(wx, wx), dMul(wy, wy));
  Dual a = dDiv(dMul(dMul(alpha, alpha), s2), z2);
  if (isinf(a.v)) return Dual(kInfinity, 0.0);
  return dDiv(a, dMul(2.0, dAdd(dSqrt(dAdd(1.0, a)), 1.0)));
}

Dual smithG2Dual(Dual3 wi, Dual3 wo, Dual alpha) {
  return dDiv(1.0, dAdd(dAdd(1.0, smithLambdaDual(wi, alpha)), smithLambdaDual(wo, alpha)));
}

Dual fresnelSchlickDual(Dual f0, Dual cosTheta) {
  Dual m = dClamp(dSub(1.0, cosTheta), 0.0, 1.0);
  Dual m2 = dMul(m, m);
  return dAdd(f0, dMul(dSub(1.0, f0), dMul(dMul(m2, m2), m)));
}

Dual fresnelDielectricDual(Dual cosI, Dual eta, out Dual cosT) {
  Dual sin2T = dDiv(dSub(1.0, dMul(cosI, cosI)), dMul(eta, eta));
  if (sin2T.v >= 1.0) {
    cosT = dual(0.0);
    return dual(1.0);
  }
  cosT = dSqrt(dSub(1.0, sin2T));
  Dual etaCosT = dMul(eta, cosT);
  Dual rs = dDiv(dSub(cosI, etaCosT), dAdd(cosI, etaCosT));
  Dual etaCosI = dMul(eta, cosI);
  Dual rp = dDiv(dSub(etaCosI, cosT), dAdd(etaCosI, cosT));
  return dMul(0.5, dAdd(dMul(rs, rs), dMul(rp, rp)));
}

Dual fresnelDielectricTransmittanceDual(Dual cosI, Dual cosT, Dual eta) {
  Dual s = dAdd(cosI, dMul(eta, cosT));
  Dual p = dAdd(dMul(eta, cosI), cosT);
  Dual scale = dMul(dMul(dMul(2.0, eta), cosI), cosT);
  return dMul(scale, dAdd(dDiv(1.0, dMul(s, s)), dDiv(1.0, dMul(p, p))));
}

// refractionHalfVector of lib/bsdf.glsl; a zero Dual3 when undefined.
Dual3 refractionHalfVectorDual(Dual3 wi, Dual3 wo, Dual eta) {
  Dual3 h = dAdd(wi, dScale(wo, eta));
  float len2 = dot(h.v, h.v);
  if (!(len2 > 1e-12)) return dual3(vec3(0.0));
  float inv = inversesqrt(len2);
  vec3 u = h.v * inv;
  Dual3 r = Dual3(u, (h.d - u * dot(u, h.d)) * inv);
  return u.z < 0.0 ? dNeg(r) : r;
}

// ---- Local evaluation (wi.z >= kBsdfMinCos) ----------------------------------------------------

Dual conductorEvalLocalDual(Dual albedo, Dual alpha, Dual3 wi, Dual3 wo) {
  if (wo.v.z < kBsdfMinCos) return dual(0.0);
  Dual3 h = dNormalize(dAdd(wi, wo));
  Dual f = fresnelSchlickDual(albedo, dDot(wi, h));
  Dual num = dMul(dMul(f, ggxDDual(h, alpha)), smithG2Dual(wi, wo, alpha));
  return dDiv(num, dMul(dMul(4.0, dZ(wi)), dZ(wo)));
}

Dual dielectricEvalLocalDual(Dual albedo, Dual alpha, Dual3 wi, Dual3 wo, Dual eta) {
  if (abs(wo.v.z) < kBsdfMinCos) return dual(0.0);
  Dual cosT;
  if (wo.v.z > 0.0) {
    Dual3 h = dNormalize(dAdd(wi, wo));
    Dual fr = fresnelDielectricDual(dDot(wi, h), eta, cosT);
    Dual d = ggxDDual(h, alpha);
    Dual num = dMul(dMul(dMul(albedo, fr), d), smithG2Dual(wi, wo, alpha));
    return dDiv(num, dMul(dMul(4.0, dZ(wi)), dZ(wo)));
  }
  Dual3 h = refractionHalfVectorDual(wi, wo, eta);
  Dual ci = dDot(wi, h);
  Dual co = dDot(wo, h);
  // Both directions must see the same microfacet from its two sides.
  if (!(ci.v > 0.0 && co.v < 0.0)) return dual(0.0);
  Dual fr = fresnelDielectricDual(ci, eta, cosT);
  Dual denom = dAdd(ci, dMul(eta, co));
  Dual denom2 = dMul(denom, denom);
  if (fr.v >= 1.0 || !(denom2.v > 0.0)) return dual(0.0);
  Dual d = ggxDDual(h, alpha);
  Dual t = fresnelDielectricTransmittanceDual(ci, cosT, eta);
  Dual num = dMul(dMul(dMul(dMul(dMul(albedo, t), d), smithG2Dual(wi, wo, alpha)), ci), dNeg(co));
  return dDiv(num, dMul(dMul(dZ(wi), dNeg(dZ(wo))), denom2));
}

// ---- Public API ---------------------------------------------------------------------------------

Dual bsdfEvalDual(GpuMaterial m, Dual albedo, Dual roughness, Dual ior, Dual3 n, Dual3 wi, Dual3 wo) {
  BsdfFrameDual fr = bsdfFrameDual(n, wi);
  Dual3 wiL = toLocalDual(fr, wi);
  Dual3 woL = toLocalDual(fr, wo);
  if (wiL.v.z < kBsdfMinCos) return dual(0.0);
  if (sceneHasMaterial(kMaterialDiffuse) && m.type == kMaterialDiffuse)
    return woL.v.z >= kBsdfMinCos ? dMul(albedo, kInvPi) : dual(0.0);
  Dual alpha = dClamp(roughness, kBsdfMinAlpha, 1.0);
  if (sceneHasMaterial(kMaterialConductor) && m.type == kMaterialConductor)
    return conductorEvalLocalDual(albedo, alpha, wiL, woL);
  if (!sceneHasMaterial(kMaterialDielectric)) return dual(0.0);
  // dielectricEta: ior = eta_inside / eta_outside, wi outside when on n's side.
  Dual eta = dot(n.v, wi.v) >= 0.0 ? ior : dDiv(1.0, ior);
  return dielectricEvalLocalDual(albedo, alpha, wiL, woL, eta);
}
#endif
