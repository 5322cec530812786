// Double-precision CPU twin of shaders/lib/bsdf.glsl: f(wi, wo) and the density of bsdfSample, for
// the same GpuMaterial and the same conventions (wi toward the camera side, wo toward the light
// side, n the geometric normal; diffuse and conductor two-sided, dielectric one-sided with n
// outside). Written from the formulas of Walter et al. 2007 in their own notation (incident and
// transmitted indices), not transcribed from the shader, so the two catch each other's slips.
#pragma once
#include <cstdint>

#include <glm/glm.hpp>

#include "vktg/gpu/shared.h"

namespace vktg::test {

// Same thresholds as the shader (kBsdfMinCos, roughness clamp).
inline constexpr double kRefMinCos = 1e-6;
inline constexpr double kRefMinAlpha = 1e-3;

double bsdfEvalReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi, const glm::dvec3& wo);
double bsdfPdfReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi, const glm::dvec3& wo);

// Largest relative change per radian of f (eval = true) or of the pdf under small random rotations
// (1e-6 rad) of n, wi and wo: the condition number that turns float rounding of the directions
// into relative error. Infinite where a rotation crosses a discontinuity (a zero on one side).
double bsdfSensitivityReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi,
                                const glm::dvec3& wo, bool eval, uint64_t seed);

// Relative error a float32 shader may make where the twin's sensitivity is kappa. The bound counts
// operations at the error Vulkan allows each ("Precision and Operation of SPIR-V Instructions"), in
// units of u = 2^-24 (half an ulp): +, -, x and fma are correctly rounded (1 u; a compiler may fuse
// or not, either is within it), x / y and 1 / x 2.5 ulp (5 u), inversesqrt 2 ulp (4 u), sqrt
// inherited from 1 / inversesqrt (9 u). A device may use all of that: NVIDIA's divisions and
// square roots are not correctly rounded, lavapipe's are (it measured about half the bound below).
//
// The shader's directions pass through some twenty roundings (frame, dot products, half vector,
// normalisation), six of them normalisations or divisions: 14 x 1 u + 6 x 9 u = 68 u of angular
// error, and the refraction half vector wi + eta wo amplifies it by up to 1 + eta (about 3.5 for
// the indices tested); the formula then amplifies the angular error by kappa. kBsdfAmplifiedUlps
// = 256 >= 68 x 3.5 bounds that chain. Worst excess measured over the random configurations of
// tests/gpu_bsdf.cpp (it prints it): 94 on lavapipe, 174 on an NVIDIA H200.
inline constexpr double kBsdfRelTolerance = 1e-4;  // well-conditioned: ~50 float operations
inline constexpr double kFloatEps = 5.96e-8;
inline constexpr double kBsdfAmplifiedUlps = 256.0;
inline double bsdfFloatTolerance(double kappa) { return kBsdfRelTolerance + kBsdfAmplifiedUlps * kFloatEps * kappa; }

// Exact unpolarised Fresnel reflectance from index etaI into etaT, cosI > 0 on the incident side.
double fresnelDielectricReference(double cosI, double etaI, double etaT);

// Index of refraction of the medium on wo's side over that on wi's side (1 for reflection).
double bsdfEtaRatioReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi,
                             const glm::dvec3& wo);

}  // namespace vktg::test
