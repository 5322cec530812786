// Reverse-mode gradient of log f for the adjoint passes (THEORY.md §7): ∂ log f / ∂n, ∂/∂wi and
// ∂/∂wo, and ∂ log f / ∂(albedo, roughness, ior), for bsdfEval of lib/bsdf.glsl.
//
// Forward mode (bsdfEvalDual) along a basis gives the gradient: f is linear in the tangent it is
// differentiated along, so g = sum_i (df along e_i) e_i. Only the parts perpendicular to n, wi and
// wo are needed, since every caller reaches them through a normalisation (whose adjoint drops the
// radial part), so each unit vector takes the two tangents of its own frame: six evaluations, and
// one per material scalar asked for. A diffuse BSDF (albedo / pi on wi's side) has no geometric
// derivative at all and costs nothing; in a scene of diffuse surfaces the rest is not compiled.
// Requires lib/common.glsl, lib/bindings.glsl (materials) and lib/bsdf_dual.glsl.
#ifndef VKTG_BSDF_GRADIENT_GLSL
#define VKTG_BSDF_GRADIENT_GLSL
#include "lib/bsdf_dual.glsl"

struct BsdfLogGradient {
  vec3 n, wi, wo;  // tangential parts
  vec3 material;   // albedo, roughness, ior
};

// f's derivative along the tangents (dn, dwi, dwo) and material rates (dm), divided by f.
float bsdfRelativeRate(GpuMaterial m, float f, vec3 n, vec3 wi, vec3 wo, vec3 dn, vec3 dwi, vec3 dwo, vec3 dm) {
  Dual d = bsdfEvalDual(m, dual(m.albedo, dm.x), dual(m.roughness, dm.y), dual(m.ior, dm.z), dual3(n, dn), dual3(wi, dwi),
                        dual3(wo, dwo));
  return d.d / f;
}

// `geometry`: the direction parts are wanted; `scalars`: the material parts.
BsdfLogGradient bsdfLogGradient(uint material, vec3 n, vec3 wi, vec3 wo, bool geometry, bool scalars) {
  BsdfLogGradient g = BsdfLogGradient(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  GpuMaterial m = materials[material];
  float f = bsdfEval(m, n, wi, wo);
  if (!(f > 0.0)) return g;
  if (sceneHasMaterial(kMaterialDiffuse) && m.type == kMaterialDiffuse) {
    g.material.x = scalars ? 1.0 / m.albedo : 0.0;
    return g;
  }
  // A scene of diffuse surfaces only compiles none of the rest (a CPU device would run it masked).
  if ((kSpecMaterialMaskValue & ~(1u << kMaterialDiffuse)) == 0u) return g;
  const vec3 zero = vec3(0.0);
  if (geometry) {
    vec3 t, b;
    basisFromNormal(n, t, b);
    g.n = bsdfRelativeRate(m, f, n, wi, wo, t, zero, zero, zero) * t + bsdfRelativeRate(m, f, n, wi, wo, b, zero, zero, zero) * b;
    basisFromNormal(wi, t, b);
    g.wi = bsdfRelativeRate(m, f, n, wi, wo, zero, t, zero, zero) * t + bsdfRelativeRate(m, f, n, wi, wo, zero, b, zero, zero) * b;
    basisFromNormal(wo, t, b);
    g.wo = bsdfRelativeRate(m, f, n, wi, wo, zero, zero, t, zero) * t + bsdfRelativeRate(m, f, n, wi, wo, zero, zero, b, zero) * b;
  }
  if (scalars) {
    g.material.x = bsdfRelativeRate(m, f, n, wi, wo, zero, zero, zero, vec3(1.0, 0.0, 0.0));
    g.material.y = bsdfRelativeRate(m, f, n, wi, wo, zero, zero, zero, vec3(0.0, 1.0, 0.0));
    if (m.type == kMaterialDielectric) g.material.z = bsdfRelativeRate(m, f, n, wi, wo, zero, zero, zero, vec3(0.0, 0.0, 1.0));
  }
  return g;
}
#endif
