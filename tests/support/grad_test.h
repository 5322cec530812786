// Derivatives inside tests (label grad): forward-mode gradient renders and finite-difference
// references with the shared test context, and the per-pixel comparison of two estimates whose
// variances are both measured (one of them possibly from few independent seeds, hence Student t).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "grad/gradient.h"
#include "support/render_test.h"
#include "vktg/gate.h"
#include "vktg/scene.h"

namespace vktg::test {

// An image estimate: per pixel the mean and the variance of that mean, with the degrees of
// freedom of the variance estimate (samples - 1; large for a render's own per-sample variance).
struct PixelEstimate {
  std::vector<float> mean;
  std::vector<float> variance;
  double dof = 0;
};

// Interior-term derivative images of `parameters` (the first gate layer), in the order given.
// Counts non-finite derivative contributions in `nonFinite`.
struct GradientImages {
  std::vector<PixelEstimate> derivatives;
  PixelEstimate primal;
  uint64_t nonFinite = 0;
  double seconds = 0;
};
GradientImages gradientInTest(const Scene& scene, const std::vector<std::string>& parameters, const RenderOptions& options);

// Central finite difference of `parameter` measured over `seeds` independent seeds (seed k renders
// the scene with render.seed = scene.render.seed + k + 1 and the scene's spp, both sides sharing it:
// common random numbers). The variance is the sample variance of the per-seed differences over
// `seeds` (dof seeds - 1), which is valid whatever the correlation of the two sides; the bound that
// finiteDifference returns, (var+ + var-) / (4 eps^2), ignores the positive correlation of common
// random numbers and grows like 1/eps^2 where the true variance stays finite.
// `halfStep` (if not null) receives, from the same seeds, the per-seed difference
// FD(eps) - FD(eps / 2), whose mean estimates 3/4 of FD(eps)'s truncation error.
struct FiniteDifferenceImages {
  PixelEstimate derivative;
  double seconds = 0;
  uint64_t nonFinite = 0;
};
FiniteDifferenceImages finiteDifferenceInTest(const Scene& scene, const std::string& parameter, double eps,
                                              uint32_t seeds, const RenderOptions& options,
                                              PixelEstimate* halfStep = nullptr);

// Per-pixel two-sided test of a against b: t = (a - b) / sqrt(va + vb) with Welch-Satterthwaite
// degrees of freedom, against the Sidak-corrected Student-t threshold for `alpha` over all pixels.
// Pixels where both variances vanish must agree exactly; a pixel where exactly one side has zero
// variance and zero mean (saw nothing) is untestable and counted.
struct Comparison {
  size_t tested = 0, untestable = 0, rejected = 0;
  double worstT = 0;
  std::string worst;  // the pixel with the largest |t|: values, t, threshold
};
Comparison compareEstimates(const PixelEstimate& a, const PixelEstimate& b, double alpha);
// The same against an exact reference value at every pixel.
Comparison compareWithExact(const PixelEstimate& a, const std::vector<double>& exact, double alpha);

// P(|T| > t) for Student's t with `dof` degrees of freedom (normal for dof > 1e6), and its inverse.
double studentTwoSidedTail(double t, double dof);
double studentTwoSidedQuantile(double tail, double dof);

// The sum over pixels as a one-pixel estimate: the pixels' estimates are independent, so their
// variances add; the dof stays one pixel's (conservative: the sum's variance is better known).
PixelEstimate imageSum(const PixelEstimate& e);

// Mean over pixels of |mean| / sqrt(variance): how far an estimate stands out of its noise.
double signalToNoise(const PixelEstimate& e);

// ----------------------------------------------------------------------------------------------
// The interior-term checks shared by tests/grad_interior.cpp and tests/grad_slow_interior.cpp.
// Every comparison is at level kGradAlpha per image (Sidak over its pixels); every gradient and
// finite-difference render must report no non-finite value. Finite differences run over 16 seeds
// with common random numbers on both sides, and each step eps is checked against eps/2.
//
// Confocal plane (test_scenes.h): point sensor and point light at height h over a Lambertian plane,
// gaussian gate mu = 2.2 h, sigma = 0.1 h. The gate's support ends at L = 2.85 h, i.e. plane points
// within r = 1.02 h of the foot point; the plane's half size is 3 h, so no path the gate sees
// touches its edge (no silhouette). With a plane point at radius r, sensor height h, light height
// hL, dS = sqrt(r^2 + h^2), dL = sqrt(r^2 + hL^2):
//   M = integral_0^inf 2 pi r f W(dS + dL) dr,  f = rho I hL h^2 / (pi dL^3 dS^4),
// whose limits do not move with h, hL or the gate, so every derivative is taken under the integral:
//   d/dhL: f (1/hL - 3 hL/dL^2) W + f W'(L) hL/dL       (light moved up)
//   d/dh:  f (2/h - 4 h/dS^2) W + f W'(L) h/dS          (sensor moved up)
//   plane moved away from both = d/dh + d/dhL,  gate centre: -f W'(L),  dM/drho = M/rho, dM/dI = M/I.
// The plane derivative is cross-checked on the CPU against the form in d (the brief's
// M = 2 rho I h^3 integral_h^inf d^-6 W(2d) dd), where the lower limit moves (Leibniz):
//   dM/dh = 3 M / h - 2 rho I h^-3 W(2h).
//
// Perspective plane: a 12x12 camera 2 m above a large plane (half size 4 m, filling the view),
// lit by a small emissive rectangle (outside the view) and a point light; gaussian gate mu = 4 m,
// sigma = 0.5 m, whose support (up to 7.25 m) no path touching the plane's edge fits in. The plane is diffuse, a rough conductor or a rough dielectric. Nothing occludes
// anything: the only shapes are the plane and the lamp, which faces the plane and lies above every
// segment from the point light or the camera to the plane. Paths transmitted into the dielectric
// leave the scene (nothing lies below it), so the ior acts through the Fresnel terms only and no
// optical length inside the medium reaches the gate.
inline constexpr double kGradAlpha = 1e-4;
inline constexpr double kConfocalHeight = 1.0, kConfocalRho = 0.6, kConfocalIntensity = 1.0;
inline constexpr double kConfocalMu = 2.2, kConfocalSigma = 0.1;

// The confocal response M and its derivatives (double precision, by quadrature in r).
struct ConfocalReference {
  double m = 0, dPlane = 0, dLight = 0, dGate = 0;
};
ConfocalReference confocalReference();

// Renders the confocal gradient of albedo, intensity, plane_h (plane moved away), light_z (light
// moved up) and gate_mu with `nee` at `spp`, and compares each with its exact value and with a
// finite difference (standard NEE, fdSpp per seed; computed once per test binary, since the
// primal's expectation does not depend on the estimator). The primal is checked against M too.
void checkConfocal(NeeMode nee, uint32_t spp, uint32_t seed, uint32_t fdSpp);

// Renders the perspective plane (diffuse, conductor or dielectric) with standard NEE and compares
// the gradient of each of `parameters` (from albedo, emission, plane_z, light_x, roughness, ior)
// with its finite difference, pixel by pixel and as image sums (whose standard error is about
// 1/12 of a pixel's relative to the signal: a bias too small for any pixel shows there).
void checkLitPlane(MaterialType type, const std::vector<std::string>& parameters, uint32_t spp, uint32_t fdSpp);

// A fixed adjoint image for loss-gradient tests: values in [-1, 1) drawn from `seed`, of both
// signs, so that every pixel's derivative counts.
ImageSet randomAdjointImage(uint32_t width, uint32_t height, uint32_t layers, uint32_t seed);

}  // namespace vktg::test
