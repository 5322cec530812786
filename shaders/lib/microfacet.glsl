// GGX / Trowbridge-Reitz microfacet pieces, isotropic, in a local frame whose z axis is the
// (side-adjusted) surface normal. Callers pass local vectors, so sin^2 comes from x, y directly
// instead of 1 - cos^2: that cancellation would cost GGX all its precision at alpha = 1e-3.
//
//   float ggxD(vec3 h, float alpha)            normal distribution D(h), h.z > 0, integrates
//                                              D(h) cos(theta_h) to 1 over the hemisphere.
//   float smithLambda(vec3 w, float alpha)     Smith Lambda of a direction (uses |w.z|).
//   float smithG1(vec3 w, float alpha)         1 / (1 + Lambda): masking of one direction.
//   float smithG2(vec3 wi, vec3 wo, float alpha)
//                                              height-correlated masking-shadowing
//                                              1 / (1 + Lambda(wi) + Lambda(wo)) (Heitz 2014). It is
//                                              exact for reflection; refraction uses the same form
//                                              (as pbrt-v4 does) instead of the beta-function one, which
//                                              keeps f symmetric under the generalised reciprocity.
//   vec3 sampleGgxVisibleNormal(vec3 wi, float alpha, vec2 u)
//                                              Heitz 2018: a microfacet normal drawn from the visible
//                                              normal density D_wi(h) = G1(wi) max(0, wi.h) D(h) / wi.z,
//                                              wi.z > 0. Always returns h.z >= 0 and wi.h >= 0.
//   float fresnelSchlick(float f0, float cosTheta)
//   float fresnelDielectric(float cosI, float eta, out float cosT)
//                                              exact unpolarised Fresnel reflectance; cosI > 0 on the
//                                              incident side, eta = eta_transmitted / eta_incident;
//                                              returns 1 with cosT = 0 under total internal reflection.
//   float fresnelDielectricTransmittance(float cosI, float cosT, float eta)
//                                              1 - F without the cancellation of forming it from F,
//                                              which near the critical angle leaves no digit.
#ifndef VKTG_MICROFACET_GLSL
#define VKTG_MICROFACET_GLSL

float ggxD(vec3 h, float alpha) {
  float a2 = alpha * alpha;
  // D = 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2) written without tan: bounded for every h.z >= 0.
  float k = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
  return 1.0 / (kPi * a2 * k * k);
}

float smithLambda(vec3 w, float alpha) {
  float z2 = w.z * w.z;
  float s2 = w.x * w.x + w.y * w.y;
  // a = alpha^2 tan^2(theta); Lambda = (sqrt(1 + a) - 1) / 2 = a / (2 (sqrt(1 + a) + 1)), the second
  // form free of cancellation when a is small (smooth surfaces, steep angles).
  float a = alpha * alpha * s2 / z2;
  if (isinf(a)) return kInfinity;
  return a / (2.0 * (sqrt(1.0 + a) + 1.0));
}

float smithG1(vec3 w, float alpha) { return 1.0 / (1.0 + smithLambda(w, alpha)); }

float smithG2(vec3 wi, vec3 wo, float alpha) {
  return 1.0 / (1.0 + smithLambda(wi, alpha) + smithLambda(wo, alpha));
}

vec3 sampleGgxVisibleNormal(vec3 wi, float alpha, vec2 u) {
  // Stretch to the hemisphere configuration (alpha = 1), where visible normals are uniform on the
  // projected hemisphere seen from vh.
  vec3 vh = normalize(vec3(alpha * wi.x, alpha * wi.y, wi.z));
  float len2 = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = len2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
  vec3 t2 = cross(vh, t1);
  // A point on the unit disk, the lower half squeezed onto the part of the projected hemisphere
  // that vh can see.
  float r = sqrt(u.x);
  float phi = 2.0 * kPi * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  // Unstretch back to the ellipsoid configuration.
  return normalize(vec3(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

float fresnelSchlick(float f0, float cosTheta) {
  float m = clamp(1.0 - cosTheta, 0.0, 1.0);
  float m2 = m * m;
  return f0 + (1.0 - f0) * (m2 * m2 * m);
}

float fresnelDielectric(float cosI, float eta, out float cosT) {
  float sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) {
    cosT = 0.0;
    return 1.0;
  }
  cosT = sqrt(1.0 - sin2T);
  float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 0.5 * (rs * rs + rp * rp);
}

float fresnelDielectricTransmittance(float cosI, float cosT, float eta) {
  // 1 - r^2 = (1 - r)(1 + r) for each polarisation, expanded: 4 eta cosI cosT / (sum)^2.
  float s = cosI + eta * cosT;
  float p = eta * cosI + cosT;
  return 2.0 * eta * cosI * cosT * (1.0 / (s * s) + 1.0 / (p * p));
}
#endif
