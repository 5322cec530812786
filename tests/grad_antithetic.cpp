// Antithetic pairs (THEORY.md §5).
// Interior term, near-delta gaussian gates, on the confocal plane with
// ellipsoidal NEE (the only sampler whose path lengths come from the gate): for sigma/mu = 1e-2 and
// 1e-3, the antithetic and plain estimators agree in mean (the image, the interior derivative of
// the plane's translation along its normal and of the gate centre), both agree with the exact
// values, and the antithetic variance of the derivatives is lower (measured; the ratio is printed).
//
// Exact values: M = 2 rho I h^3 int d^-6 W(2d) dd over the gate's support (test_scenes.h,
// confocalGated, 16-point Gauss-Legendre on 256 panels), differentiated by central differences in
// double: in h with step 1e-4 (M is smooth in h on the scale h), in the gate centre with step
// sigma / 1000 (truncation ~1e-7 relative).
//
// Path-length-boundary term, narrow box gates [mu (1 - r), mu (1 + r)]: the pass connects to both
// jumps with shared random numbers instead of choosing one. On the confocal plane (r = 1e-2, 1e-3;
// closed forms in tests/grad_boundary.cpp) and on the separated sensor and light with the light
// moving (r = 1e-2; no closed form: antithetic against plain, and each against finite
// differences would need an FD step below the gate's width, so only the two estimators meet), the
// two estimators agree in mean, and the antithetic variance is lower at equal samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/boundary_test.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

constexpr double kRho = 0.8, kIntensity = 1.0, kHeight = 1.0, kMu = 2.8, kAlpha = 1e-3;
constexpr uint32_t kSpp = 100000;
// Quantities compared per gate (image, d/dt, d/dc) times comparisons per quantity (antithetic vs
// plain, each vs exact) times the two gates.
constexpr size_t kComparisons = 3 * 3 * 2;
// The antithetic derivative variance must be below this fraction of the plain one. Each variance
// is estimated from kSpp samples; if the pairs did not help, the ratio of the two estimates would
// stay within a few times sqrt(2 (kurtosis - 1) / kSpp) of 1, far above this bound for any
// kurtosis these estimators show (the measured ratios are printed).
constexpr double kMaxVarianceRatio = 0.5;

double response(double h, double mu, double sigma) {
  auto w = [&](double len) { return gaussianWeight(len, mu, sigma); };
  return confocalGated(h, kRho, kIntensity, w, mu - kGaussianCutoff * sigma, mu + kGaussianCutoff * sigma);
}

Scene nearDeltaScene(double sigma, uint32_t seed) {
  Scene scene = confocalPlaneScene(kHeight, 2.0, 2.0, kRho, kIntensity);
  scene.gate = gaussianGate(kMu, sigma);
  scene.render.spp = kSpp;
  scene.render.seed = seed;
  scene.render.maxDepth = 2;
  addTranslation(scene, "t", "plane", {0.0f, 0.0f, 1.0f});
  addGateCenter(scene, "c");
  return scene;
}

struct Estimates {
  LayerEstimate image, dt, dc;
  double seconds = 0;
};

Estimates render(const Scene& scene, AntitheticMode mode) {
  GradientOptions options;
  options.render.nee = NeeMode::Ellipsoidal;
  options.antithetic = mode;
  options.edges = false;  // the plane's rim is outside the gate (see grad_boundary.cpp)
  GradientResult g = renderGradient(testRenderer(), scene, {"t", "c"}, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  EXPECT_EQ(g.plan.antithetic, mode == AntitheticMode::On);
  EXPECT_FALSE(g.plan.pathLength) << "a gaussian gate has no jumps";
  Estimates e;
  e.image = layerOf(g.primal.mean, g.primal.variance, 0);
  e.dt = layerOf(g.interior.derivatives[0], g.interior.variances[0], 0);
  e.dc = layerOf(g.interior.derivatives[1], g.interior.variances[1], 0);
  e.seconds = g.stats.seconds;
  const RenderStats& st = g.primal.stats;
  std::printf("    %s: paths %llu, shadow rays %llu, ellipsoid queries %llu (empty %llu), batches %u x %u\n",
              mode == AntitheticMode::On ? "antithetic" : "plain", (unsigned long long)st.paths,
              (unsigned long long)st.shadowRays, (unsigned long long)st.ellipsoidQueries,
              (unsigned long long)st.ellipsoidEmpty, st.batches, st.batchSize);
  return e;
}

void expectAgree(const char* what, const LayerEstimate& a, const LayerEstimate& b) {
  PixelCheck c = checkPixels(a, b, sidakLevel(kAlpha, kComparisons));
  EXPECT_EQ(c.rejected, 0u) << what << ": " << c.worst;
  std::printf("    %-30s %s\n", what, c.worst.c_str());
}

void checkGate(double sigmaOverMu, uint32_t seed) {
  double sigma = sigmaOverMu * kMu;
  std::printf("  sigma/mu = %g\n", sigmaOverMu);
  Scene scene = nearDeltaScene(sigma, seed);
  Estimates plain = render(scene, AntitheticMode::Off);
  scene.render.seed = seed + 1;
  Estimates pairs = render(scene, AntitheticMode::On);

  double image = response(kHeight, kMu, sigma);
  constexpr double kStepH = 1e-4;
  double dt = -(response(kHeight + kStepH, kMu, sigma) - response(kHeight - kStepH, kMu, sigma)) / (2 * kStepH);
  double stepC = 1e-3 * sigma;
  double dc = (response(kHeight, kMu + stepC, sigma) - response(kHeight, kMu - stepC, sigma)) / (2 * stepC);

  expectAgree("image: antithetic vs plain", pairs.image, plain.image);
  // The antithetic image's standard error (~1e-7 relative at sigma/mu = 1e-3) is below what a
  // float32 renderer resolves: its gate weights and inverse densities carry a systematic error of
  // a few tens of ulps. Against the exact value, allow 32 ulps (2^-19 relative) as a floor.
  expectAgree("image: antithetic vs exact", pairs.image, exactLayer({image}, std::ldexp(1.0, -19)));
  expectAgree("image: plain vs exact", plain.image, exactLayer({image}));
  expectAgree("d/dt: antithetic vs plain", pairs.dt, plain.dt);
  expectAgree("d/dt: antithetic vs exact", pairs.dt, exactLayer({dt}));
  expectAgree("d/dt: plain vs exact", plain.dt, exactLayer({dt}));
  expectAgree("d/dc: antithetic vs plain", pairs.dc, plain.dc);
  expectAgree("d/dc: antithetic vs exact", pairs.dc, exactLayer({dc}));
  expectAgree("d/dc: plain vs exact", plain.dc, exactLayer({dc}));

  double ratioImage = pairs.image.variance[0] / plain.image.variance[0];
  double ratioT = pairs.dt.variance[0] / plain.dt.variance[0];
  double ratioC = pairs.dc.variance[0] / plain.dc.variance[0];
  std::printf("    variance ratio antithetic / plain (equal samples; x2 for equal connections): image %.3g, "
              "d/dt %.3g, d/dc %.3g; time plain %.2f s, antithetic %.2f s\n",
              ratioImage, ratioT, ratioC, plain.seconds, pairs.seconds);
  EXPECT_LT(ratioT, kMaxVarianceRatio) << "d/dt: antithetic pairs did not lower the variance";
  EXPECT_LT(ratioC, kMaxVarianceRatio) << "d/dc: antithetic pairs did not lower the variance";
}

TEST(GradAntithetic, NearDeltaSigmaOverMu1em2) { checkGate(1e-2, 101); }

TEST(GradAntithetic, NearDeltaSigmaOverMu1em3) { checkGate(1e-3, 201); }

// The path-length-boundary term alone (no interior pass) of `parameters`, pairs on or off.
TermImages boundaryTerm(const Scene& scene, const std::vector<std::string>& parameters, AntitheticMode mode) {
  GradientOptions options;
  options.render.nee = NeeMode::Ellipsoidal;
  options.antithetic = mode;
  options.interior = options.edges = false;
  GradientResult g = renderGradient(testRenderer(), scene, parameters, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  EXPECT_TRUE(g.plan.pathLength);
  EXPECT_EQ(g.plan.antithetic, mode == AntitheticMode::On);
  std::printf("    %s: %.2f s, ellipsoid queries %llu\n", mode == AntitheticMode::On ? "antithetic" : "plain",
              g.stats.seconds, (unsigned long long)g.stats.ellipsoidQueries);
  return g.pathLength;
}

// Antithetic against plain (and each against `exact` when given) for every parameter; returns the
// variance ratios antithetic / plain. `jumpScale`: the size of one jump's share of the term, which
// sets the float32 rounding of the pairs' difference (see checkBoxPairs).
std::vector<double> compareBoundary(const Scene& scene, const std::vector<std::string>& parameters,
                                    const std::vector<double>& exact, const std::vector<double>& jumpScale = {}) {
  TermImages plain = boundaryTerm(scene, parameters, AntitheticMode::Off);
  Scene other = scene;
  other.render.seed += 1;
  TermImages pairs = boundaryTerm(other, parameters, AntitheticMode::On);
  size_t comparisons = parameters.size() * (exact.empty() ? 1 : 3);
  std::vector<double> ratios;
  for (size_t p = 0; p < parameters.size(); ++p) {
    LayerEstimate a = layerOf(pairs.derivatives[p], pairs.variances[p], 0);
    LayerEstimate b = layerOf(plain.derivatives[p], plain.variances[p], 0);
    auto agree = [&](const std::string& what, const LayerEstimate& x, const LayerEstimate& y) {
      PixelCheck c = checkPixels(x, y, sidakLevel(kAlpha, comparisons));
      EXPECT_EQ(c.rejected, 0u) << what << ": " << c.worst;
      std::printf("    %-40s %s\n", what.c_str(), c.worst.c_str());
    };
    agree("d/d" + parameters[p] + " boundary: antithetic vs plain", a, b);
    if (!exact.empty()) {
      double floor = std::ldexp(1.0, -19) * jumpScale[p] / std::abs(exact[p]);
      agree("d/d" + parameters[p] + " boundary: antithetic vs exact", a, exactLayer({exact[p]}, floor));
      agree("d/d" + parameters[p] + " boundary: plain vs exact", b, exactLayer({exact[p]}));
    }
    ratios.push_back(a.variance[0] / b.variance[0]);
    std::printf("    d/d%s variance ratio antithetic / plain (equal samples, twice the connections): %.3g\n",
                parameters[p].c_str(), ratios.back());
  }
  return ratios;
}

void checkBoxPairs(double r, uint32_t seed) {
  double a = kMu * (1 - r), b = kMu * (1 + r);
  std::printf("  confocal box [%g, %g]\n", a, b);
  Scene scene = boundary::confocalBoxScene(a, b, kSpp, seed);
  std::vector<double> exact = {-boundary::confocalBoxDh(kHeight, a, b).boundary, boundary::confocalBoxDc(kHeight, a, b)};
  // Each pair is the difference of two float32 connections of nearly equal size (the jump at a
  // alone: 2 rho I h^4 (a/2)^-7 for t, rho I h^3 (a/2)^-6 for c); on the confocal plane the pair's
  // standard error is far below their rounding, so allow 32 ulps of one connection as a floor
  // (measured at r = 1e-3: 7 ulps off).
  std::vector<double> jumpScale = {2 * kRho * kIntensity * std::pow(kHeight, 4) * std::pow(a / 2, -7.0),
                                   kRho * kIntensity * std::pow(kHeight, 3) * std::pow(a / 2, -6.0)};
  for (double ratio : compareBoundary(scene, {"t", "c"}, exact, jumpScale))
    EXPECT_LT(ratio, kMaxVarianceRatio) << "antithetic pairs did not lower the boundary term's variance";
}

TEST(GradAntithetic, BoundaryPairsBoxWidth1em2) { checkBoxPairs(1e-2, 301); }

TEST(GradAntithetic, BoundaryPairsBoxWidth1em3) { checkBoxPairs(1e-3, 401); }

// Sensor and light 1 apart at height 1: the jumps' ellipses carry a varying integrand (on the
// confocal plane each jump's circle carries a constant one).
TEST(GradAntithetic, BoundaryPairsSeparatedLight) {
  Scene scene = boundary::separatedBoxScene(kMu * (1 - 1e-2), kMu * (1 + 1e-2), kSpp, 501);
  for (double ratio : compareBoundary(scene, {"lx", "lz"}, {}))
    EXPECT_LT(ratio, kMaxVarianceRatio) << "antithetic pairs did not lower the boundary term's variance";
}

}  // namespace
}  // namespace vktg::test
