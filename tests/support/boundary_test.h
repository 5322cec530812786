// Helpers of the path-length-boundary and antithetic derivative tests (grad_boundary,
// grad_antithetic): the renderer they share, parameters added to the C++ test scenes, seed-wise
// finite differences with common random numbers, and per-pixel comparisons whose thresholds come
// from the measured standard errors (Sidak-corrected over every comparison of a test).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>

#include "grad/gradient.h"
#include "support/chi2.h"
#include "support/render_test.h"
#include "support/test_scenes.h"
#include "vktg/scene.h"

namespace vktg::test {


// Adds a parameter to a test scene (θ = 0 as built).
void addTranslation(Scene& scene, const std::string& name, const std::string& shape, glm::vec3 axis);
void addLightMove(Scene& scene, const std::string& name, const std::string& light, glm::vec3 axis);
void addGateCenter(Scene& scene, const std::string& name);

// An estimate of one image layer: per pixel the mean and the variance of that mean; `dof` is the
// degrees of freedom of the variance estimate (seeds - 1 for a spread over seeds; a render's own
// per-sample variance over many samples counts as normal: kNormalDof).
// `unresolved` (empty: none) marks pixels whose variance was not estimated: a spread over seeds
// in which no seed saw any change (a rare event, such as a silhouette crossing by an in-gate path,
// that every seed of the finite difference missed; its variance estimate 0 is no estimate).
inline constexpr double kNormalDof = 1e9;
struct LayerEstimate {
  std::vector<double> mean, variance;
  double dof = kNormalDof;
  std::vector<bool> unresolved;
  bool isUnresolved(size_t i) const { return !unresolved.empty() && unresolved[i]; }
};
LayerEstimate layerOf(const ImageSet& mean, const ImageSet& variance, uint32_t layer);
// Pixel-wise sum of the layers (variances add: used where the layers are independent estimates or
// where an upper bound on the variance of the sum is wanted).
LayerEstimate sumLayers(const std::vector<LayerEstimate>& layers);
// Sum over pixels, with the variance of that sum (pixels are independent).
LayerEstimate sumPixels(const LayerEstimate& e);
// Sums over tiles of tile x tile pixels of an image `width` pixels wide (row-major, sides
// multiples of the tile): for estimates too sparse to see every pixel.
LayerEstimate sumTiles(const LayerEstimate& e, size_t width, size_t tile);

// Central finite difference (I(θ + eps) - I(θ - eps)) / (2 eps) of every gate layer over `seeds`
// seeds: seed k renders both sides with render.seed = scene.render.seed + 1000 (k + 1) (common
// random numbers). Mean and variance over the per-seed differences (dof seeds - 1): valid whatever
// the correlation between the two sides, which finiteDifference's bound ignores.
struct SeedDifference {
  std::vector<LayerEstimate> layers;
  uint64_t nonFinite = 0;
  double seconds = 0;
};
SeedDifference seedFiniteDifference(const Scene& scene, const std::string& parameter, double eps, uint32_t seeds,
                                    const RenderOptions& options);


// Per-pixel test of a against b (or an exact value: b with zero variance): t = (a - b) / sqrt(va + vb)
// against the Student-t threshold (Welch-Satterthwaite dof) for the per-test level `level`. A pixel
// unresolved on either side that the test would reject is counted in `unresolved` instead: that
// side's zero variance is no estimate (a difference that rests only on the other side's error).
struct PixelCheck {
  size_t tested = 0, rejected = 0, unresolved = 0;
  double worstT = 0;
  std::string worst;  // the pixel with the largest |t|
};
PixelCheck checkPixels(const LayerEstimate& a, const LayerEstimate& b, double level);
// An exact reference; `relativeFloor` treats it as uncertain by that relative amount (one
// standard deviation), for float32 rounding the renderer cannot resolve below.
LayerEstimate exactLayer(const std::vector<double>& values, double relativeFloor = 0.0);

// The scenes, closed forms and checks grad_boundary and grad_slow_boundary share: the confocal plane
// (h = 1, rho = 0.8, I = 1) with a box gate, and renders that print what they compare.
namespace boundary {

inline constexpr double kRho = 0.8, kIntensity = 1.0, kHeight = 1.0, kAlpha = 1e-3;
inline constexpr uint32_t kFdSeeds = 16;
inline constexpr uint32_t kPerspectiveResolution = 16, kPerspectiveSpp = 1024;

struct BoxTerms {
  double total, interior, boundary;
};

// d/dh of the confocal box response and its split (derivation at the top of tests/grad_boundary.cpp).
inline BoxTerms confocalBoxDh(double h, double a, double b) {
  double d1 = 0.5 * a, d2 = 0.5 * b;
  double p5 = std::pow(d1, -5.0) - std::pow(d2, -5.0), p7 = std::pow(d1, -7.0) - std::pow(d2, -7.0);
  BoxTerms t;
  t.total = 1.2 * kRho * kIntensity * h * h * p5;
  t.interior = 2.0 * kRho * kIntensity * (0.6 * h * h * p5 - std::pow(h, 4.0) * p7);
  t.boundary = 2.0 * kRho * kIntensity * std::pow(h, 4.0) * p7;
  return t;
}

inline double confocalBoxDc(double h, double a, double b) {
  return -kRho * kIntensity * h * h * h * (std::pow(0.5 * a, -6.0) - std::pow(0.5 * b, -6.0));
}

// A checked comparison of one named estimate (every pixel) against a reference.
struct Checker {
  double level;
  void expect(const char* what, const LayerEstimate& a, const LayerEstimate& b) const {
    PixelCheck c = checkPixels(a, b, level);
    EXPECT_EQ(c.rejected, 0u) << what << ": " << c.rejected << " of " << c.tested << " pixels differ; worst " << c.worst;
    // Rare events stay rare: a reference blind at many pixels is a broken test, not a pass.
    EXPECT_LE(c.unresolved, c.tested / 20) << what << ": " << c.unresolved << " of " << c.tested << " pixels unresolved";
    std::printf("  %-44s worst %s; %zu unresolved\n", what, c.worst.c_str(), c.unresolved);
  }
};

// Box gate [a, b], spp and seed, max depth 2 (sensor -> plane -> light).
inline void boxGateAndBudget(Scene& scene, double a, double b, uint32_t spp, uint32_t seed) {
  scene.gate.type = GateType::Box;
  scene.gate.a = a;
  scene.gate.b = b;
  scene.render.spp = spp;
  scene.render.seed = seed;
  scene.render.maxDepth = 2;
}

inline Scene confocalBoxScene(double a, double b, uint32_t spp, uint32_t seed) {
  Scene scene = confocalPlaneScene(kHeight, 2.0, 2.0, kRho, kIntensity);
  boxGateAndBudget(scene, a, b, spp, seed);
  addTranslation(scene, "t", "plane", {0.0f, 0.0f, 1.0f});
  addGateCenter(scene, "c");
  return scene;
}

// Sensor and light 1 m apart at height 1 above the plane (half-extent 2 x 2), box gate [a, b],
// max depth 2 (sensor -> plane -> light); parameters lx and lz move the light along x and z.
inline Scene separatedBoxScene(double a, double b, uint32_t spp, uint32_t seed) {
  Scene scene = separatedPlaneScene(1.0, 1.0, 2.0, 2.0, kRho, kIntensity);
  boxGateAndBudget(scene, a, b, spp, seed);
  addLightMove(scene, "lx", "light", {1.0f, 0.0f, 0.0f});
  addLightMove(scene, "lz", "light", {0.0f, 0.0f, 1.0f});
  return scene;
}

inline GradientResult gradient(const Scene& scene, const std::vector<std::string>& parameters, NeeMode nee,
                        uint32_t sppBoundary = 0) {
  GradientOptions options;
  options.render.nee = nee;
  options.sppBoundary = sppBoundary;
  // No occluder, and the gate keeps every path away from the plane's rim: no visibility boundary
  // contributes, so these tests leave the edge pass out (tests/grad_edge.cpp runs it).
  options.edges = false;
  GradientResult g = renderGradient(testRenderer(), scene, parameters, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  std::printf("  gradient (%s nee, %zu parameters): %.2f s\n", neeModeName(g.primal.plan.nee), parameters.size(),
              g.stats.seconds);
  return g;
}

inline LayerEstimate term(const TermImages& t, size_t parameter, uint32_t layer = 0) {
  return layerOf(t.derivatives.at(parameter), t.variances.at(parameter), layer);
}

// Box gate [2.4, 3.2] at h = 1: sensor distances d in [1.2, 1.6], inside the plane's inscribed
// disk (radius 2 > sqrt(1.6^2 - 1)), so the infinite-plane closed forms hold.
inline constexpr double kBoxA = 2.4, kBoxB = 3.2;

// The confocal box scene with a truncated gaussian gate (mu, sigma) on its support [kBoxA, kBoxB].
inline Scene truncatedGaussianScene(double mu, double sigma, uint32_t spp, uint32_t seed) {
  Scene scene = confocalBoxScene(kBoxA, kBoxB, spp, seed);
  scene.gate.type = GateType::TruncatedGaussian;
  scene.gate.mu = mu;
  scene.gate.sigma = sigma;
  return scene;
}

// Its exact derivatives along t and c: the double-precision quadrature of M (test_scenes.h)
// differentiated by a central difference of step 1e-3 (error ~1e-7 relative: exact here).
struct TruncatedGaussianDerivatives {
  double dt, dc;
};
inline TruncatedGaussianDerivatives truncatedGaussianDerivatives(double mu, double sigma) {
  auto response = [&](double h, double shift) {
    auto w = [&](double len) { return std::exp(-0.5 * std::pow((len - mu - shift) / sigma, 2.0)); };
    return confocalGated(h, kRho, kIntensity, w, kBoxA + shift, kBoxB + shift);
  };
  constexpr double kStep = 1e-3;
  return {-(response(kHeight + kStep, 0) - response(kHeight - kStep, 0)) / (2 * kStep),
          (response(kHeight, kStep) - response(kHeight, -kStep)) / (2 * kStep)};
}

}  // namespace boundary

}  // namespace vktg::test
