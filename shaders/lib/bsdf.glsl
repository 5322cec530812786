// Surface scattering of the three materials of include/vktg/gpu/shared.h (monochromatic).
// Requires lib/common.glsl and the GpuMaterial struct (vktg/gpu/shared.h) to be included first.
//
// Directions are unit vectors pointing away from the surface: wi toward the previous path vertex
// (the camera side), wo toward the next one (the light side). n is the geometric unit normal.
//
//   float bsdfEval(GpuMaterial m, vec3 n, vec3 wi, vec3 wo)
//       f(wi, wo) without the cosine factor, in the radiance convention of camera-to-light path
//       tracing (for refraction f(wo, wi) = (eta_wo / eta_wi)^2 f(wi, wo)).
//   float bsdfPdf(GpuMaterial m, vec3 n, vec3 wi, vec3 wo)
//       solid-angle density with which bsdfSample produces wo. It integrates to the probability
//       that bsdfSample returns true (below 1 where microfacet samples can leave the valid side).
//   bool bsdfSample(GpuMaterial m, vec3 n, vec3 wi, vec3 u, out BsdfSample s)
//       u in [0,1)^3 (u.z picks reflection or refraction). s.weight = f |cos(n, wo)| / pdf, computed
//       in closed form; false when no direction is produced: grazing wi, or a microfacet sample
//       that points to the wrong side of the geometric surface.
//
// Materials:
//   diffuse     Lambert, f = albedo / pi, cosine-weighted sampling. Two-sided.
//   conductor   GGX with alpha = roughness, height-correlated Smith masking-shadowing, Schlick
//               Fresnel with F0 = albedo; visible-normal sampling (Heitz 2018). Two-sided.
//   dielectric  rough dielectric (Walter et al. 2007) with GGX, height-correlated Smith, exact
//               Fresnel; ior = eta_inside / eta_outside, n points outside. Sampling picks a
//               visible normal, then reflects with probability F and refracts otherwise. albedo
//               tints both lobes. Refraction carries no eta^2 in f: toward the denser medium the
//               weight is G2 / (G1 eta^2), the radiance scaling of camera-to-light transport.
//               ior must differ from 1 (a rough interface with eta = 1 degenerates to a delta).
// Two-sided materials reflect on wi's side: n is flipped to that side. Roughness is clamped to
// [1e-3, 1]. Directions within kBsdfMinCos of the tangent plane get f = pdf = 0 and no sample,
// which keeps every quantity finite (the 1/cos factors are bounded by 1/kBsdfMinCos).
#ifndef VKTG_BSDF_GLSL
#define VKTG_BSDF_GLSL
#include "lib/microfacet.glsl"
#include "lib/specialization.glsl"
#include "lib/warp.glsl"

struct BsdfSample {
  vec3 wo;
  float weight;
  float pdf;
  bool transmitted;
};

const float kBsdfMinCos = 1e-6;
const float kBsdfMinAlpha = 1e-3;

float bsdfAlpha(GpuMaterial m) { return clamp(m.roughness, kBsdfMinAlpha, 1.0); }

// Local frame around the normal turned to wi's side: z = cos to that normal.
struct BsdfFrame {
  vec3 t;
  vec3 b;
  vec3 n;
};

BsdfFrame bsdfFrame(vec3 n, vec3 wi) {
  BsdfFrame f;
  f.n = dot(n, wi) >= 0.0 ? n : -n;
  basisFromNormal(f.n, f.t, f.b);
  return f;
}

vec3 toLocal(BsdfFrame f, vec3 w) { return vec3(dot(w, f.t), dot(w, f.b), dot(w, f.n)); }
vec3 toWorld(BsdfFrame f, vec3 w) { return w.x * f.t + w.y * f.b + w.z * f.n; }

// Relative index eta_wo / eta_wi for refraction through the dielectric, wi on `outside`'s side.
float dielectricEta(GpuMaterial m, bool outside) { return outside ? m.ior : 1.0 / m.ior; }

// Half vector of a refraction pair (local frame, wi.z > 0, wo.z < 0), turned to +z; zero vector
// when undefined.
vec3 refractionHalfVector(vec3 wi, vec3 wo, float eta) {
  vec3 h = wi + eta * wo;
  float len2 = dot(h, h);
  if (!(len2 > 1e-12)) return vec3(0.0);
  h *= inversesqrt(len2);
  return h.z < 0.0 ? -h : h;
}

// ---- Evaluation and density, local frame (wi.z >= kBsdfMinCos) ----------------------------------

float microfacetReflectionPdf(vec3 wi, vec3 h, float alpha) {
  // Visible-normal density over the reflection Jacobian 1 / (4 wi.h): the wi.h cancels.
  return smithG1(wi, alpha) * ggxD(h, alpha) / (4.0 * wi.z);
}

float conductorEvalLocal(GpuMaterial m, vec3 wi, vec3 wo) {
  if (wo.z < kBsdfMinCos) return 0.0;
  float alpha = bsdfAlpha(m);
  vec3 h = normalize(wi + wo);
  float f = fresnelSchlick(m.albedo, dot(wi, h));
  return f * ggxD(h, alpha) * smithG2(wi, wo, alpha) / (4.0 * wi.z * wo.z);
}

float conductorPdfLocal(GpuMaterial m, vec3 wi, vec3 wo) {
  if (wo.z < kBsdfMinCos) return 0.0;
  float alpha = bsdfAlpha(m);
  return microfacetReflectionPdf(wi, normalize(wi + wo), alpha);
}

// Shared by eval and pdf of the dielectric: f and pdf of one lobe given the local pair.
void dielectricLocal(GpuMaterial m, vec3 wi, vec3 wo, float eta, out float f, out float pdf) {
  f = 0.0;
  pdf = 0.0;
  if (abs(wo.z) < kBsdfMinCos) return;
  float alpha = bsdfAlpha(m);
  float cosT;
  if (wo.z > 0.0) {
    vec3 h = normalize(wi + wo);
    float fr = fresnelDielectric(dot(wi, h), eta, cosT);
    float d = ggxD(h, alpha);
    f = m.albedo * fr * d * smithG2(wi, wo, alpha) / (4.0 * wi.z * wo.z);
    pdf = fr * microfacetReflectionPdf(wi, h, alpha);
    return;
  }
  vec3 h = refractionHalfVector(wi, wo, eta);
  float ci = dot(wi, h);
  float co = dot(wo, h);
  // Both directions must see the same microfacet from its two sides.
  if (!(ci > 0.0 && co < 0.0)) return;
  float fr = fresnelDielectric(ci, eta, cosT);
  float denom = ci + eta * co;
  float denom2 = denom * denom;
  if (fr >= 1.0 || !(denom2 > 0.0)) return;
  float d = ggxD(h, alpha);
  float t = fresnelDielectricTransmittance(ci, cosT, eta);
  f = m.albedo * t * d * smithG2(wi, wo, alpha) * ci * (-co) / (wi.z * (-wo.z) * denom2);
  // Visible-normal density times the refraction Jacobian |dh/dwo| = eta^2 |wo.h| / (wi.h + eta wo.h)^2.
  pdf = t * smithG1(wi, alpha) * d * ci / wi.z * eta * eta * (-co) / denom2;
}

// ---- Public API ---------------------------------------------------------------------------------

float bsdfEval(GpuMaterial m, vec3 n, vec3 wi, vec3 wo) {
  BsdfFrame fr = bsdfFrame(n, wi);
  vec3 wiL = toLocal(fr, wi);
  vec3 woL = toLocal(fr, wo);
  if (wiL.z < kBsdfMinCos) return 0.0;
  if (sceneHasMaterial(kMaterialDiffuse) && m.type == kMaterialDiffuse)
    return woL.z >= kBsdfMinCos ? m.albedo * kInvPi : 0.0;
  if (sceneHasMaterial(kMaterialConductor) && m.type == kMaterialConductor) return conductorEvalLocal(m, wiL, woL);
  if (!sceneHasMaterial(kMaterialDielectric)) return 0.0;
  float f;
  float pdf;
  dielectricLocal(m, wiL, woL, dielectricEta(m, dot(n, wi) >= 0.0), f, pdf);
  return f;
}

float bsdfPdf(GpuMaterial m, vec3 n, vec3 wi, vec3 wo) {
  BsdfFrame fr = bsdfFrame(n, wi);
  vec3 wiL = toLocal(fr, wi);
  vec3 woL = toLocal(fr, wo);
  if (wiL.z < kBsdfMinCos) return 0.0;
  if (sceneHasMaterial(kMaterialDiffuse) && m.type == kMaterialDiffuse)
    return woL.z >= kBsdfMinCos ? woL.z * kInvPi : 0.0;
  if (sceneHasMaterial(kMaterialConductor) && m.type == kMaterialConductor) return conductorPdfLocal(m, wiL, woL);
  if (!sceneHasMaterial(kMaterialDielectric)) return 0.0;
  float f;
  float pdf;
  dielectricLocal(m, wiL, woL, dielectricEta(m, dot(n, wi) >= 0.0), f, pdf);
  return pdf;
}

bool bsdfSample(GpuMaterial m, vec3 n, vec3 wi, vec3 u, out BsdfSample s) {
  s.wo = vec3(0.0);
  s.weight = 0.0;
  s.pdf = 0.0;
  s.transmitted = false;
  BsdfFrame fr = bsdfFrame(n, wi);
  vec3 wiL = toLocal(fr, wi);
  if (wiL.z < kBsdfMinCos) return false;

  if (sceneHasMaterial(kMaterialDiffuse) && m.type == kMaterialDiffuse) {
    vec3 woL = sampleCosineHemisphere(u.xy);
    if (woL.z < kBsdfMinCos) return false;
    s.wo = toWorld(fr, woL);
    s.pdf = woL.z * kInvPi;
    s.weight = m.albedo;
    return true;
  }

  // Only the material code the scene needs survives specialisation (kSpecMaterialMask).
  if (!sceneHasMaterial(kMaterialConductor) && !sceneHasMaterial(kMaterialDielectric)) return false;
  float alpha = bsdfAlpha(m);
  vec3 h = sampleGgxVisibleNormal(wiL, alpha, u.xy);
  float ci = dot(wiL, h);
  if (!(ci > 0.0)) return false;
  float g1 = smithG1(wiL, alpha);
  float d = ggxD(h, alpha);

  if (sceneHasMaterial(kMaterialConductor) && m.type == kMaterialConductor) {
    vec3 woL = 2.0 * ci * h - wiL;
    if (woL.z < kBsdfMinCos) return false;
    s.wo = toWorld(fr, woL);
    s.pdf = g1 * d / (4.0 * wiL.z);
    s.weight = fresnelSchlick(m.albedo, ci) * smithG2(wiL, woL, alpha) / g1;
    return true;
  }

  if (!sceneHasMaterial(kMaterialDielectric)) return false;
  float eta = dielectricEta(m, dot(n, wi) >= 0.0);
  float cosT;
  float fresnel = fresnelDielectric(ci, eta, cosT);
  if (u.z < fresnel) {
    vec3 woL = 2.0 * ci * h - wiL;
    if (woL.z < kBsdfMinCos) return false;
    s.wo = toWorld(fr, woL);
    s.pdf = fresnel * g1 * d / (4.0 * wiL.z);
    s.weight = m.albedo * smithG2(wiL, woL, alpha) / g1;
    return true;
  }
  // Snell's law about h: the tangential parts of wi and eta * wo cancel.
  vec3 woL = (ci / eta - cosT) * h - wiL / eta;
  if (woL.z > -kBsdfMinCos) return false;
  float co = -cosT;  // wo . h
  float denom = ci + eta * co;
  float denom2 = denom * denom;
  if (!(denom2 > 0.0)) return false;
  s.wo = toWorld(fr, woL);
  s.pdf = fresnelDielectricTransmittance(ci, cosT, eta) * g1 * d * ci / wiL.z * eta * eta * cosT / denom2;
  s.weight = m.albedo * smithG2(wiL, woL, alpha) / (g1 * eta * eta);
  s.transmitted = true;
  return true;
}
#endif
