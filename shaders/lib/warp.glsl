// Sampling warps: maps from uniform numbers in [0,1)^2 to directions and points with known densities.
//
//   vec3 sampleCosineHemisphere(vec2 u)   local frame (z up), density cos(theta) / pi (solid angle);
//                                         concentric disk mapping (Shirley & Chiu 1997) lifted to the
//                                         hemisphere, which keeps strata compact (good for QMC).
//   vec3 sampleUniformSphere(vec2 u)      density 1 / (4 pi) (solid angle).
//   vec2 sampleTriangleBarycentrics(vec2 u)
//                                         (b1, b2) uniform over the triangle by area: the point is
//                                         (1 - b1 - b2) p0 + b1 p1 + b2 p2 (the HitRecord convention).
//   void basisFromNormal(vec3 n, out vec3 t, out vec3 b)
//                                         orthonormal right-handed frame (t, b, n) for a unit n,
//                                         branch-free except for the sign of n.z (Duff et al. 2017),
//                                         continuous everywhere except across n.z = 0's sign change.
#ifndef VKTG_WARP_GLSL
#define VKTG_WARP_GLSL

vec2 sampleConcentricDisk(vec2 u) {
  vec2 p = 2.0 * u - 1.0;
  if (p.x == 0.0 && p.y == 0.0) return vec2(0.0);
  float r;
  float phi;
  if (abs(p.x) > abs(p.y)) {
    r = p.x;
    phi = (0.25 * kPi) * (p.y / p.x);
  } else {
    r = p.y;
    phi = 0.5 * kPi - (0.25 * kPi) * (p.x / p.y);
  }
  return r * vec2(cos(phi), sin(phi));
}

vec3 sampleCosineHemisphere(vec2 u) {
  vec2 d = sampleConcentricDisk(u);
  // max(): rounding can push |d| a hair above 1 at the disk's rim.
  float z = sqrt(max(0.0, 1.0 - dot(d, d)));
  return vec3(d, z);
}

vec3 sampleUniformSphere(vec2 u) {
  float z = 1.0 - 2.0 * u.x;
  float r = sqrt(max(0.0, (1.0 - z) * (1.0 + z)));  // factored: accurate near the poles
  float phi = 2.0 * kPi * u.y;
  return vec3(r * cos(phi), r * sin(phi), z);
}

vec2 sampleTriangleBarycentrics(vec2 u) {
  // Square-root parameterisation: the first coordinate's marginal is linear, as the area demands.
  float s = sqrt(u.x);
  return vec2(1.0 - s, u.y * s);
}

void basisFromNormal(vec3 n, out vec3 t, out vec3 b) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}
#endif
