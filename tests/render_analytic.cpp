// Analytic scenes with known answers (DESIGN.md §5 "render"): the confocal Lambertian plane under a
// co-located point light and point sensor (closed form in path length, tests/support/test_scenes.h
// derives it) for box, gaussian and steady gates with standard and ellipsoidal NEE, and the diffuse
// furnace. Every comparison is a z-test against the exact value with the render's measured
// standard error (alpha 1e-3, Sidak-corrected over pixels).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "support/render_test.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

constexpr double kRho = 0.6, kIntensity = 1.0, kHeight = 1.0;

// Renders and checks the single pixel of a point sensor against an exact value.
void expectPointSensor(const Scene& scene, NeeMode nee, double reference) {
  RenderOptions options;
  options.nee = nee;
  RenderResult r = renderInTest(scene, options);
  EXPECT_EQ(r.stats.nonFinite, 0u);
  // The estimator asked for is the one that ran: the plan says so, and only ellipsoidal
  // connections query ellipsoids.
  EXPECT_EQ(r.plan.nee, nee) << "asked for " << neeModeName(nee) << ", ran " << neeModeName(r.plan.nee);
  if (nee == NeeMode::Standard) EXPECT_EQ(r.stats.ellipsoidQueries, 0u);
  else EXPECT_GT(r.stats.ellipsoidQueries, 0u);
  ASSERT_EQ(r.mean.layers.size(), 1u);
  const std::vector<float>& mean = r.mean.layers[0].pixels;
  const std::vector<float>& variance = r.variance.layers[0].pixels;
  ASSERT_EQ(mean.size(), 1u);
  ZTestResult z = zTest(mean, variance, {float(reference)}, {0.0f});
  EXPECT_EQ(z.rejected, 0u) << "expected " << reference << ", " << z.worst << " (nee " << neeModeName(r.plan.nee)
                            << ", relative standard error " << std::sqrt(variance[0]) / reference << ")";
  EXPECT_GT(variance[0], 0.0f) << "a Monte Carlo estimate with zero variance cannot be z-tested";
  std::printf("  %s nee: %.6g (reference %.6g, se %.3g, %.2f s)\n", neeModeName(r.plan.nee), mean[0], reference,
              std::sqrt(variance[0]), r.stats.seconds);
}

Scene confocal(double halfSize, uint32_t spp, uint32_t seed) {
  Scene scene = confocalPlaneScene(kHeight, halfSize, halfSize, kRho, kIntensity);
  scene.render.spp = spp;
  scene.render.seed = seed;
  return scene;
}

// Box gate [2.1 h, 2.6 h]: sensor distances d in [1.05 h, 1.3 h], which stay inside the plane's
// inscribed disk (radius 2 h > sqrt(1.3^2 - 1) h), so the infinite-plane closed form is exact.
TEST(RenderAnalytic, ConfocalPlaneBoxGate) {
  Scene scene = confocal(2.0, 100000, 11);
  scene.gate.type = GateType::Box;
  scene.gate.a = 2.1;
  scene.gate.b = 2.6;
  double reference = confocalBox(kHeight, kRho, kIntensity, 2.1, 2.6);
  expectPointSensor(scene, NeeMode::Standard, reference);
  scene.render.seed = 12;
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference);
}

// Gaussian gate mu = 2.4 h, sigma = 0.1 h: support up to 3.05 h, d <= 1.525 h, inside the disk of
// radius 2 h again. Part of the support lies below the shortest path 2h (no response there).
TEST(RenderAnalytic, ConfocalPlaneGaussianGate) {
  Scene scene = confocal(2.0, 100000, 21);
  scene.gate = gaussianGate(2.4, 0.1);
  double lo = 2.4 - kGaussianCutoff * 0.1, hi = 2.4 + kGaussianCutoff * 0.1;
  double reference = confocalGated(
      kHeight, kRho, kIntensity, [](double l) { return gaussianWeight(l, 2.4, 0.1); }, lo, hi);
  expectPointSensor(scene, NeeMode::Standard, reference);
  scene.render.seed = 22;
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference);
}

// Normalised gaussian (W divided by sigma sqrt(2 pi)): the same response scaled by that factor.
TEST(RenderAnalytic, ConfocalPlaneNormalizedGaussianGate) {
  Scene scene = confocal(2.0, 50000, 31);
  scene.gate = gaussianGate(2.3, 0.05, true);
  double lo = 2.3 - kGaussianCutoff * 0.05, hi = 2.3 + kGaussianCutoff * 0.05;
  double reference = confocalGated(
                         kHeight, kRho, kIntensity, [](double l) { return gaussianWeight(l, 2.3, 0.05); }, lo, hi) /
                     (0.05 * std::sqrt(2.0 * std::numbers::pi));
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference);
}

// Steady: the square of half side 4 h loses the part of 2 rho I / (5 h^2) outside it (about 2e-3
// of it); confocalSteadySquare integrates the square exactly.
TEST(RenderAnalytic, ConfocalPlaneSteady) {
  Scene scene = confocal(4.0, 100000, 41);
  double reference = confocalSteadySquare(kHeight, 4.0, kRho, kIntensity);
  double infinite = 2.0 * kRho * kIntensity / (5.0 * kHeight * kHeight);
  EXPECT_LT(reference, infinite);
  EXPECT_GT(reference, infinite * (1.0 - 1e-2));
  expectPointSensor(scene, NeeMode::Standard, reference);
}

// Furnace: inside a closed box whose faces all emit Le and reflect with albedo rho, every path
// vertex sees radiance Le, so paths of k + 1 segments carry Le rho^k. With paths of at most
// maxDepth segments (render.maxDepth counts vertices after the camera) the radiance is
// Le * sum_{k=0}^{maxDepth-1} rho^k (Russian roulette is unbiased); a point sensor sees pi times it.
double furnaceRadiance(double le, double rho, uint32_t maxDepth) {
  double sum = 0, term = 1;
  for (uint32_t k = 0; k < maxDepth; ++k, term *= rho) sum += term;
  return le * sum;
}

TEST(RenderAnalytic, FurnacePointSensorDeep) {
  // rho^64 ~ 5e-20: the geometric series has converged; roulette starts at depth 4.
  Scene scene = furnaceScene(1.0, 0.5, 1.0, true, 1);
  scene.render.maxDepth = 64;
  scene.render.spp = 50000;
  scene.render.seed = 51;
  expectPointSensor(scene, NeeMode::Standard, std::numbers::pi * furnaceRadiance(1.0, 0.5, 64));
}

TEST(RenderAnalytic, FurnacePointSensorTruncated) {
  // maxDepth 3 with rho = 0.7: the omitted term rho^3 is 15% of the truncated sum, so counting one
  // depth too many or too few fails.
  Scene scene = furnaceScene(1.0, 0.7, 1.0, true, 1);
  scene.render.maxDepth = 3;
  scene.render.rouletteDepth = 2;
  scene.render.spp = 50000;
  scene.render.seed = 52;
  expectPointSensor(scene, NeeMode::Standard, std::numbers::pi * furnaceRadiance(1.0, 0.7, 3));
}

TEST(RenderAnalytic, FurnacePerspective) {
  Scene scene = furnaceScene(1.0, 0.5, 2.0, false, 8);
  scene.render.maxDepth = 4;
  scene.render.rouletteDepth = 2;
  scene.render.spp = 1024;
  scene.render.seed = 53;
  RenderResult r = renderInTest(scene, {});
  EXPECT_EQ(r.stats.nonFinite, 0u);
  const std::vector<float>& mean = r.mean.layers[0].pixels;
  const std::vector<float>& variance = r.variance.layers[0].pixels;
  double reference = furnaceRadiance(2.0, 0.5, 4);
  ZTestResult z = zTest(mean, variance, std::vector<float>(mean.size(), float(reference)),
                        std::vector<float>(mean.size(), 0.0f));
  EXPECT_EQ(z.rejected, 0u) << "expected " << reference << " everywhere; " << z.worst;
  ImageMean m = imageMean(mean, variance);
  EXPECT_LT(std::abs(m.mean - reference), 3.29 * m.standardError)
      << "image mean " << m.mean << " vs " << reference << " (se " << m.standardError << ")";
  std::printf("  furnace perspective: %.6g (reference %.6g, se %.3g, %.2f s)\n", m.mean, reference,
              m.standardError, r.stats.seconds);
}

}  // namespace
}  // namespace vktg::test
