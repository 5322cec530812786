// The path-length-boundary term (THEORY.md §3) and the interior term beside it, on scenes without
// occlusion or moving silhouettes (the edge pass is left out here; tests/grad_edge.cpp runs it):
//  1. closed forms on the confocal plane with a box gate: the total derivative of the plane's
//     translation along its normal and of the gate centre, and each term on its own;
//  2. central finite differences (common random numbers, spread over seeds) for the confocal
//     scene (translation and gate centre), a light position, and a pinhole camera over a plane
//     (the other NEE modes, and the truncated gaussian gate against finite differences, are in
//     grad_slow_boundary.cpp: each new pipeline variant costs lavapipe 5-20 s to compile on a cold
//     cache);
//  2b. the truncated gaussian gate against quadrature, at a reduced budget;
//  3. a transient stack (bins covering every path length): the bins' derivatives sum to the
//     derivative of the steady image, each bin's boundary image matches the closed form of the
//     flux through its two edges, and each bin matches finite differences.
// Every comparison is a t-test with the measured standard errors of both sides, Sidak-corrected
// (alpha 1e-3) over all comparisons of its test.
//
// Confocal plane (tests/support/test_scenes.h): height h, albedo rho, intensity I. A plane point at
// sensor distance d = sqrt(r^2 + h^2) contributes f = rho I h^3 / (pi d^7) per unit area at path
// length 2d, so with dA = 2 pi d dd and a box gate [a, b] (h < a/2, d1 = a/2, d2 = b/2)
//   M(h)      = 2 rho I h^3 int_{d1}^{d2} d^-6 dd = (2/5) rho I h^3 (d1^-5 - d2^-5)
//   dM/dh     = (6/5) rho I h^2 (d1^-5 - d2^-5)                       (d1, d2 do not depend on h)
// Material form (a plane point keeps its (x, y) while h changes): the interior term holds the gate
// window fixed on the material points whose length lies in [a, b] and differentiates f only:
//   interior  = 2 rho I int_{d1}^{d2} (3 h^2 d^-6 - 7 h^4 d^-8) dd
//             = 2 rho I [(3/5) h^2 (d1^-5 - d2^-5) - h^4 (d1^-7 - d2^-7)]
// (d/dh of h^3 d^-7 at fixed r is 3 h^2 d^-7 - 7 h^4 d^-9). The boundary term at a jump s = 2d_s:
// the circle r_s carries f with dL/dh = 2h/d and |grad_r L| = 2r/d, so
//   Delta W(s) int f (dL/dh) / |grad L| r dphi = Delta W(s) 2 rho I h^4 d_s^-7,
//   boundary  = 2 rho I h^4 (d1^-7 - d2^-7)       (Delta W = +1 at a, -1 at b)
// and interior + boundary = dM/dh. With h = 1, a = 2.4, b = 3.2 the interior term even has the
// wrong sign. The plane's translation t along its normal (+z) is h = h0 - t: every d/dt = -d/dh.
// Gate centre c (W_c(L) = W(L - c)): the jumps move to a + c, b + c, so
//   dM/dc = -rho I h^3 (d1^-6 - d2^-6)      (the interior term is 0: W' = 0 inside the box)
// and the boundary term is all of it (dL/dc - 1 = -1 on the circle: Delta W(s) rho I h^3 d_s^-6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "support/boundary_test.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

using namespace boundary;

TEST(GradBoundary, ConfocalBoxClosedFormSplit) {
  Scene scene = confocalBoxScene(kBoxA, kBoxB, 100000, 7);
  GradientResult g = gradient(scene, {"t", "c"}, NeeMode::Ellipsoidal);
  ASSERT_TRUE(g.plan.pathLength);
  ASSERT_EQ(g.pathLength.derivatives.size(), 2u);
  BoxTerms dh = confocalBoxDh(kHeight, kBoxA, kBoxB);
  double dc = confocalBoxDc(kHeight, kBoxA, kBoxB);
  Checker check{sidakLevel(kAlpha, 6)};
  check.expect("d/dt total", term(g.total, 0), exactLayer({-dh.total}));
  check.expect("d/dt interior", term(g.interior, 0), exactLayer({-dh.interior}));
  check.expect("d/dt path-length boundary", term(g.pathLength, 0), exactLayer({-dh.boundary}));
  check.expect("d/dc total", term(g.total, 1), exactLayer({dc}));
  check.expect("d/dc interior", term(g.interior, 1), exactLayer({0.0}));
  check.expect("d/dc path-length boundary", term(g.pathLength, 1), exactLayer({dc}));
  // Without the boundary term the derivative is not merely noisy but wrong: here of the wrong sign.
  LayerEstimate interior = term(g.interior, 0), total = term(g.total, 0);
  EXPECT_GT(std::abs(interior.mean[0] - total.mean[0]), 1.0 * std::abs(total.mean[0]))
      << "interior " << interior.mean[0] << " vs total " << total.mean[0];
  std::printf("  interior / total = %.3f (closed form %.3f)\n", interior.mean[0] / total.mean[0], dh.interior / dh.total);
}

// Finite differences of the same scene: both parameters, every term that runs.
// Truncation: the central difference of the closed form at this step differs from dM/dh by
// (eps^2 / 6) times the third derivative, ~1e-5 relative, asserted below to stay under a tenth of
// the measured error.
TEST(GradBoundary, ConfocalBoxFiniteDifference) {
  Scene scene = confocalBoxScene(kBoxA, kBoxB, 100000, 17);
  GradientResult g = gradient(scene, {"t", "c"}, NeeMode::Ellipsoidal);
  Scene fdScene = confocalBoxScene(kBoxA, kBoxB, 20000, 18);
  constexpr double kEps = 0.01;
  RenderOptions fdOptions;
  fdOptions.nee = NeeMode::Ellipsoidal;
  SeedDifference ft = seedFiniteDifference(fdScene, "t", kEps, kFdSeeds, fdOptions);
  SeedDifference fc = seedFiniteDifference(fdScene, "c", kEps, kFdSeeds, fdOptions);
  EXPECT_EQ(ft.nonFinite + fc.nonFinite, 0u);
  std::printf("  finite differences: %.2f s\n", ft.seconds + fc.seconds);
  Checker check{sidakLevel(kAlpha, 2)};
  check.expect("d/dt total vs FD", term(g.total, 0), ft.layers[0]);
  check.expect("d/dc total vs FD", term(g.total, 1), fc.layers[0]);
  double truncation = std::abs((confocalBox(kHeight - kEps, kRho, kIntensity, kBoxA, kBoxB) -
                                confocalBox(kHeight + kEps, kRho, kIntensity, kBoxA, kBoxB)) / (2 * kEps) +
                               confocalBoxDh(kHeight, kBoxA, kBoxB).total);
  EXPECT_LT(truncation, 0.1 * std::sqrt(ft.layers[0].variance[0])) << "FD step too large";
}


// Separated sensor and light (distance 1, height 1, shortest path sqrt(5) = 2.24) with a box gate
// [2.5, 3.0]: the light moves along x (away from the sensor) and along z. The gate's ellipses
// (semi-axes at most 1.06 x 1.0) stay inside the plane's 2 x 2 half-extent.
TEST(GradBoundary, SeparatedLightPosition) {
  auto makeScene = [](uint32_t spp, uint32_t seed) { return separatedBoxScene(2.5, 3.0, spp, seed); };
  GradientResult g = gradient(makeScene(100000, 47), {"lx", "lz"}, NeeMode::Ellipsoidal);
  ASSERT_TRUE(g.plan.pathLength);
  RenderOptions fdOptions;
  fdOptions.nee = NeeMode::Ellipsoidal;
  SeedDifference fx = seedFiniteDifference(makeScene(20000, 48), "lx", 0.01, kFdSeeds, fdOptions);
  SeedDifference fz = seedFiniteDifference(makeScene(20000, 49), "lz", 0.01, kFdSeeds, fdOptions);
  EXPECT_EQ(fx.nonFinite + fz.nonFinite, 0u);
  Checker check{sidakLevel(kAlpha, 2)};
  check.expect("d/dlx total vs FD", term(g.total, 0), fx.layers[0]);
  check.expect("d/dlz total vs FD", term(g.total, 1), fz.layers[0]);
  std::printf("  d/dlx: interior %.5g + boundary %.5g; d/dlz: interior %.5g + boundary %.5g\n",
              term(g.interior, 0).mean[0], term(g.pathLength, 0).mean[0], term(g.interior, 1).mean[0],
              term(g.pathLength, 1).mean[0]);
}

// A perspective camera 2 m above a plane that fills its view (half-extent 0.73 m at 40 degrees;
// the plane's is 3 m), 16 x 16 pixels; the plane translates along its normal. No silhouette and no
// shadow moves. The paths have one or two segments, whose vertex the pixel fixes: their whole
// path-length-boundary term comes from connect_camera_boundary (connections from the camera,
// splatted). Per pixel and summed over the image against finite differences of step 0.001: at 0.01
// the jump's curve moves a third of a pixel either way and finite differences smear it over
// neighbouring pixels (60 of 256 rejected, the image sum still agreeing).
Scene perspectivePlaneScene(uint32_t spp, uint32_t seed, double a, double b, uint32_t maxDepth) {
  Scene scene = confocalPlaneScene(1.0, 3.0, 3.0, kRho, kIntensity);
  scene.camera = pinholeCamera({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 40.0f, kPerspectiveResolution);
  scene.gate.type = GateType::Box;
  scene.gate.a = a;
  scene.gate.b = b;
  scene.render.spp = spp;
  scene.render.seed = seed;
  scene.render.maxDepth = maxDepth;
  addTranslation(scene, "t", "plane", {0.0f, 0.0f, 1.0f});
  return scene;
}

void expectPerspectiveMatchesFd(const std::function<Scene(uint32_t spp, uint32_t seed)>& makeScene) {
  GradientResult g = gradient(makeScene(kPerspectiveSpp, 57), {"t"}, NeeMode::Auto);
  ASSERT_TRUE(g.plan.pathLengthFromCamera);
  SeedDifference ft = seedFiniteDifference(makeScene(kPerspectiveSpp / 4, 58), "t", 0.001, kFdSeeds, {});
  EXPECT_EQ(ft.nonFinite, 0u);
  LayerEstimate total = term(g.total, 0);
  Checker check{sidakLevel(kAlpha, total.mean.size() + 1)};
  check.expect("d/dt total vs FD, per pixel", total, ft.layers[0]);
  check.expect("d/dt total vs FD, image sum", sumPixels(total), sumPixels(ft.layers[0]));
  std::printf("  image sums: total %.5g, interior %.5g, boundary %.5g, FD %.5g\n", sumPixels(total).mean[0],
              sumPixels(term(g.interior, 0)).mean[0], sumPixels(term(g.pathLength, 0)).mean[0],
              sumPixels(ft.layers[0]).mean[0]);
}

// Two segments, camera -> plane -> a point light at (0.5, 0.3, 1.5): lengths span [3.55, 4.44] over
// the image and the box gate [3.7, 4.0] cuts across it. Without the connections from the pinhole
// the image sum was 8.84 against finite differences -62.7.
TEST(GradBoundary, PerspectiveBoxFiniteDifference) {
  expectPerspectiveMatchesFd([](uint32_t spp, uint32_t seed) {
    Scene scene = perspectivePlaneScene(spp, seed, 3.7, 4.0, 2);
    scene.pointLights[0].position = {0.5f, 0.3f, 1.5f};
    return scene;
  });
}

// One segment: the plane is an emitter (radiance 1, black) seen directly, no other light; camera
// distances span [2, 2.25] and the box gate [2.05, 2.2] cuts a ring.
TEST(GradBoundary, PerspectiveEmitterSeenDirectly) {
  expectPerspectiveMatchesFd([](uint32_t spp, uint32_t seed) {
    Scene scene = perspectivePlaneScene(spp, seed, 2.05, 2.2, 1);
    scene.pointLights.clear();
    scene.shapes[0].emission = 1.0f;
    scene.materials[0].albedo = 0.0f;
    return scene;
  });
}

// The term's two estimators run apart (as the term pilot of `vktg optimize` times them): each alone
// gives its own part, the two add up to the term (same seeds; to float rounding, since splatted
// samples reach the film by float atomics in no fixed order), and the connections from the camera
// take their own sample count. Max depth 3, so that both run behind the pinhole; a wall beside the
// plane (out of the camera's view) gives the connections from path vertices interreflections to
// place on the jumps, which a lone plane cannot have.
TEST(GradBoundary, EstimatorsRunApartAddUpToTheTerm) {
  Scene scene = perspectivePlaneScene(4, 61, 3.7, 4.0, 3);
  scene.pointLights[0].position = {0.5f, 0.3f, 1.5f};
  Shape wall;
  wall.name = "wall";
  addQuad(wall, {1.0f, -3.0f, 0.0f}, {1.0f, -3.0f, 1.5f}, {1.0f, 3.0f, 1.5f}, {1.0f, 3.0f, 0.0f});  // facing -x
  scene.shapes.push_back(std::move(wall));
  GradientOptions options;
  options.interior = options.edges = false;
  options.sppBoundaryCamera = 8;
  auto run = [&](bool perPixel, bool fromCamera) {
    GradientOptions o = options;
    o.pathLengthPerPixel = perPixel, o.pathLengthFromCamera = fromCamera;
    return renderGradient(testRenderer(), scene, {"t"}, o);
  };
  const GradientResult both = run(true, true), perPixel = run(true, false), fromCamera = run(false, true);
  EXPECT_TRUE(both.plan.pathLengthPerPixel && both.plan.pathLengthFromCamera);
  EXPECT_TRUE(perPixel.plan.pathLengthPerPixel && !perPixel.plan.pathLengthFromCamera);
  EXPECT_TRUE(!fromCamera.plan.pathLengthPerPixel && fromCamera.plan.pathLengthFromCamera);
  // Paths beyond the primal render's (the interior term, which would make the image, is off).
  const uint64_t pixels = uint64_t(kPerspectiveResolution) * kPerspectiveResolution;
  auto termPaths = [](const GradientResult& g) { return g.stats.paths - g.primal.stats.paths; };
  EXPECT_EQ(termPaths(perPixel), pixels * 4);
  EXPECT_EQ(termPaths(fromCamera), pixels * 8);
  EXPECT_EQ(termPaths(both), pixels * 12);
  const std::vector<float>& sum = both.pathLength.derivatives.at(0).layers.at(0).pixels;
  const std::vector<float>& a = perPixel.pathLength.derivatives.at(0).layers.at(0).pixels;
  const std::vector<float>& b = fromCamera.pathLength.derivatives.at(0).layers.at(0).pixels;
  ASSERT_EQ(sum.size(), a.size());
  double camera = 0, vertices = 0, largest = 0;
  for (float x : sum) largest = std::max(largest, double(std::abs(x)));
  for (size_t i = 0; i < sum.size(); ++i) {
    // A float sum of a few thousand splats in another order: a relative 1e-4 is far above its rounding
    // and far below any part of the term gone missing.
    EXPECT_NEAR(sum[i], double(a[i]) + b[i], 1e-4 * (std::abs(a[i]) + std::abs(b[i]) + 1e-3 * largest)) << "pixel " << i;
    camera += std::abs(b[i]);
    vertices += std::abs(a[i]);
  }
  // Both estimators carry part of the term here, so the sum checks each of them.
  EXPECT_GT(camera, 0.0) << "the camera's connections carry this scene's jumps";
  EXPECT_GT(vertices, 0.0) << "the connections from path vertices carry the interreflections' jumps";
}

// Truncated gaussian gate (mu 2.8, sigma 0.3, support [2.4, 3.2]): the interior and boundary terms
// are both non-zero; the totals against the differentiated quadrature (grad_slow_boundary.cpp
// runs the same at five times the samples, with finite differences too).
TEST(GradBoundary, ConfocalTruncatedGaussianQuadrature) {
  constexpr double kMu = 2.8, kSigma = 0.3;
  TruncatedGaussianDerivatives reference = truncatedGaussianDerivatives(kMu, kSigma);
  GradientResult g = gradient(truncatedGaussianScene(kMu, kSigma, 20000, 47), {"t", "c"}, NeeMode::Ellipsoidal);
  ASSERT_TRUE(g.plan.pathLength);
  Checker check{sidakLevel(kAlpha, 2)};
  check.expect("d/dt total vs quadrature", term(g.total, 0), exactLayer({reference.dt}));
  check.expect("d/dc total vs quadrature", term(g.total, 1), exactLayer({reference.dc}));
  // The boundary term is far from zero for both parameters: without it the totals would fail.
  for (size_t k = 0; k < 2; ++k)
    EXPECT_GT(std::abs(term(g.pathLength, k).mean[0]), 5 * std::sqrt(term(g.pathLength, k).variance[0])) << k;
}

// Transient stack: bins of 0.25 m over [0.1, 3.6] cover every path of the confocal square (half-size
// 1, h = 1: lengths 2 to 2 sqrt(3) = 3.46) with maxDepth 2 (sensor -> plane -> light only). No bin
// edge sits at the shortest path 2h: a bin starting exactly there has a response with a kink at
// θ = 0 (zero on one side, linear on the other), where no derivative exists.
//  - Summed over bins, the derivative is the steady one: d/dt of confocalSteadySquare (exact
//    quadrature, differentiated by a central difference of step 1e-3).
//  - Summed over bins, the boundary pass gives zero: each internal jump adds -1 to the bin below and
//    +1 to the bin above. (Its variance, taken as the sum of the bins', over-covers the anti-
//    correlated sum: the test then shows the sum is not systematically away from zero.)
//  - Each bin matches finite differences.
TEST(GradBoundary, TransientStack) {
  constexpr uint32_t kBins = 14;
  constexpr double kBinStart = 0.1, kBinWidth = 0.25;
  auto makeScene = [](uint32_t spp, uint32_t seed) {
    Scene scene = confocalPlaneScene(kHeight, 1.0, 1.0, kRho, kIntensity);
    scene.gate.type = GateType::Bins;
    scene.gate.binStart = kBinStart;
    scene.gate.binWidth = kBinWidth;
    scene.gate.binCount = kBins;
    scene.render.spp = spp;
    scene.render.seed = seed;
    scene.render.maxDepth = 2;
    addTranslation(scene, "t", "plane", {0.0f, 0.0f, 1.0f});
    return scene;
  };
  GradientResult g = gradient(makeScene(100000, 67), {"t"}, NeeMode::Ellipsoidal);
  ASSERT_TRUE(g.plan.pathLength);
  ASSERT_EQ(g.total.derivatives[0].layers.size(), kBins);
  RenderOptions fdOptions;
  fdOptions.nee = NeeMode::Ellipsoidal;
  SeedDifference fd = seedFiniteDifference(makeScene(20000, 68), "t", 0.01, kFdSeeds, fdOptions);
  EXPECT_EQ(fd.nonFinite, 0u);
  std::vector<LayerEstimate> totals, boundaries;
  for (uint32_t k = 0; k < kBins; ++k) {
    totals.push_back(term(g.total, 0, k));
    boundaries.push_back(term(g.pathLength, 0, k));
  }
  constexpr double kStep = 1e-3;
  double steady = -(confocalSteadySquare(kHeight + kStep, 1.0, kRho, kIntensity) -
                    confocalSteadySquare(kHeight - kStep, 1.0, kRho, kIntensity)) / (2 * kStep);
  // Each bin's boundary term is the flux through its lower edge minus that through its upper one.
  // Through an edge at path length e > 2h the flux is 2 rho I h^4 (e/2)^-7 (header) while the circle
  // of such paths, r = sqrt((e/2)^2 - h^2), stays inside the square plane (r <= 1, e <= 2 sqrt 2),
  // and 0 below e = 2h where no path is that short. (Summed over all bins the fluxes cancel by
  // construction, so only bin by bin is this a check.)
  auto flux = [](double e) { return e > 2 * kHeight ? 2 * kRho * kIntensity * std::pow(kHeight, 4) * std::pow(0.5 * e, -7.0) : 0.0; };
  auto edge = [&](uint32_t k) { return kBinStart + kBinWidth * k; };
  uint32_t closedFormBins = 0;
  while (std::pow(0.5 * edge(closedFormBins + 1), 2) - kHeight * kHeight <= 1.0) ++closedFormBins;
  ASSERT_GE(closedFormBins, 8u);
  Checker check{sidakLevel(kAlpha, kBins + 1 + closedFormBins)};
  check.expect("sum over bins vs steady d/dt", sumLayers(totals), exactLayer({steady}));
  for (uint32_t k = 0; k < closedFormBins; ++k) {
    std::string what = "bin " + std::to_string(k) + " boundary vs closed form";
    // d/dt = -d/dh (header).
    check.expect(what.c_str(), boundaries[k], exactLayer({-(flux(edge(k)) - flux(edge(k + 1)))}));
  }
  double boundaryScale = 0;
  for (uint32_t k = 0; k < kBins; ++k) {
    std::string what = "bin " + std::to_string(k) + " vs FD";
    check.expect(what.c_str(), totals[k], fd.layers[k]);
    boundaryScale += std::abs(boundaries[k].mean[0]);
    std::printf("  bin %2u: total %.5g (interior %.5g, boundary %.5g), FD %.5g\n", k, totals[k].mean[0],
                term(g.interior, 0, k).mean[0], boundaries[k].mean[0], fd.layers[k].mean[0]);
  }
  // The bins' boundary images are far from zero one by one: the cancellation is not vacuous.
  EXPECT_GT(boundaryScale, 10.0 * std::sqrt(sumLayers(boundaries).variance[0]));
}

}  // namespace
}  // namespace vktg::test
