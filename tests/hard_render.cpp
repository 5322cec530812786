// Numerical stability of whole renders (DESIGN.md §5 hard cases): a gate below the shortest path
// (exact zero), near-delta gaussian gates, an ellipsoid barely longer than its focal distance, an
// ellipsoid tangent to a surface, tiny and huge scene scales, and grazing light. Stable means no
// non-finite value anywhere and agreement with the exact response (tests/support/test_scenes.h)
// within the render's measured standard error (z-test, alpha 1e-3).
#include <gtest/gtest.h>

#include <cmath>

#include "support/render_test.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

constexpr double kRho = 0.6;

RenderResult render(const Scene& scene, NeeMode nee) {
  RenderOptions options;
  options.nee = nee;
  RenderResult r = renderInTest(scene, options);
  EXPECT_EQ(r.stats.nonFinite, 0u) << neeModeName(nee);
  EXPECT_EQ(r.plan.nee, nee);
  return r;
}

void expectPointSensor(const Scene& scene, NeeMode nee, double reference, const char* what) {
  RenderResult r = render(scene, nee);
  const std::vector<float>& mean = r.mean.layers.at(0).pixels;
  const std::vector<float>& variance = r.variance.layers.at(0).pixels;
  ASSERT_EQ(mean.size(), 1u);
  EXPECT_TRUE(std::isfinite(mean[0]) && std::isfinite(variance[0]));
  EXPECT_GT(variance[0], 0.0f) << what << ": no sample reached the gate";
  ZTestResult z = zTest(mean, variance, {float(reference)}, {0.0f});
  EXPECT_EQ(z.rejected, 0u) << what << " (" << neeModeName(nee) << "): expected " << reference << ", " << z.worst
                            << ", relative standard error " << std::sqrt(variance[0]) / reference;
  std::printf("  %s, %s nee: %.6g vs %.6g (z = %.2f, relative se %.2g, %.2f s)\n", what, neeModeName(nee), mean[0],
              reference, std::abs(mean[0] - reference) / std::sqrt(variance[0]), std::sqrt(variance[0]) / reference,
              r.stats.seconds);
}

void expectExactZero(const Scene& scene, NeeMode nee) {
  RenderResult r = render(scene, nee);
  for (size_t k = 0; k < r.mean.layers.size(); ++k)
    for (size_t i = 0; i < r.mean.layers[k].pixels.size(); ++i) {
      ASSERT_EQ(r.mean.layers[k].pixels[i], 0.0f) << neeModeName(nee) << " pixel " << i;
      ASSERT_EQ(r.variance.layers[k].pixels[i], 0.0f) << neeModeName(nee) << " pixel " << i;
    }
  EXPECT_EQ(r.stats.paths, uint64_t(r.mean.layers[0].pixels.size()) * scene.render.spp);
}

// Confocal plane at height h: the shortest path is 2h (sensor -> foot point -> light). Box
// [0.25 h, 1.9 h] and a gaussian whose cut-off support ends at 1.0 h + 6.5 * 0.1 h = 1.65 h lie
// wholly below it.
TEST(HardRender, GateBelowShortestPathConfocal) {
  Scene scene = confocalPlaneScene(1.0, 3.0, 3.0, kRho, 1.0);
  scene.render.spp = 20000;
  scene.gate.type = GateType::Box;
  scene.gate.a = 0.25;
  scene.gate.b = 1.9;
  expectExactZero(scene, NeeMode::Standard);
  expectExactZero(scene, NeeMode::Ellipsoidal);
  scene.gate = gaussianGate(1.0, 0.1);
  expectExactZero(scene, NeeMode::Standard);
  expectExactZero(scene, NeeMode::Ellipsoidal);
}

// Perspective Cornell room: every path from the camera (0, 0, 3.2) to a light is at least as long
// as the straight line to the nearest light point (triangle inequality): the area light's corner
// (0, 0.98, 0.3) at 3.06 m, the point light at 3.95 m. Gate [1, 3] lies below both.
TEST(HardRender, GateBelowShortestPathCornell) {
  Scene scene = cornellScene(12, 6.0, 1.5, false);
  scene.render.spp = 32;
  scene.gate.type = GateType::Box;
  scene.gate.a = 1.0;
  scene.gate.b = 3.0;
  expectExactZero(scene, NeeMode::Standard);
  expectExactZero(scene, NeeMode::Ellipsoidal);
  scene.gate.type = GateType::Bins;
  scene.gate.binStart = 0.5;
  scene.gate.binWidth = 0.5;
  scene.gate.binCount = 5;
  expectExactZero(scene, NeeMode::Standard);
  expectExactZero(scene, NeeMode::Ellipsoidal);
}

// Near-delta gaussians centred on path length 2.2 h of the confocal plane (h = 1): sigma/mu = 1e-3
// and 1e-5. The response is M = 2 rho I h^3 integral d^-6 W(2d) dd, about rho I h^3 (1.1 h)^-6
// sigma sqrt(2 pi); the sensor's float length resolves 2.2 to 2.4e-7 = sigma / 92 at 1e-5.
// At such gates every ellipsoidal sample is worth nearly the same: by symmetry a sample at length
// s is worth sigma sqrt(2 pi) M(s), and M ~ s^-6 varies by at most 6 * 6.5 sigma / (mu - 6.5 sigma)
// over the gate. The renderer's one-pass float variance cancels to 0 for so small a spread, so
// the standard error is bounded with that range instead, and the float32 film sum of n samples
// adds at most (n - 1) 2^-24 of the mean (Higham's bound for sums of non-negative terms), the
// sample's own float arithmetic a few hundred ulps (256 2^-24, as tests/hard_ellipsoid.cpp).
void nearDelta(double relativeSigma, uint32_t seed) {
  const double mu = 2.2, sigma = relativeSigma * mu;
  const uint32_t spp = 2000;
  Scene scene = confocalPlaneScene(1.0, 2.0, 2.0, kRho, 1.0);
  scene.render.spp = spp;
  scene.render.seed = seed;
  scene.gate = gaussianGate(mu, sigma);
  double reference = confocalGated(
      1.0, kRho, 1.0, [&](double l) { return gaussianWeight(l, mu, sigma); }, mu - kGaussianCutoff * sigma,
      mu + kGaussianCutoff * sigma);
  RenderResult r = render(scene, NeeMode::Ellipsoidal);
  float mean = r.mean.layers.at(0).pixels.at(0), variance = r.variance.layers.at(0).pixels.at(0);
  ASSERT_TRUE(std::isfinite(mean) && std::isfinite(variance));
  double spread = 6.0 * kGaussianCutoff * sigma / (mu - kGaussianCutoff * sigma) * reference;
  double se = std::max(double(std::sqrt(variance)), spread / std::sqrt(double(spp)));
  double floatError = (spp - 1 + 256) * std::ldexp(1.0, -24) * reference;
  double tolerance = 3.29 * se + floatError;
  EXPECT_LE(std::abs(mean - reference), tolerance)
      << "sigma/mu " << relativeSigma << ": " << mean << " vs " << reference << " (se " << se << ", float bound "
      << floatError << ")";
  std::printf("  sigma/mu %.0e: %.8g vs %.8g (relative difference %.2g, tolerance %.2g)\n", relativeSigma, mean,
              reference, std::abs(mean - reference) / reference, tolerance / reference);
}

TEST(HardRender, NearDeltaGaussian1e3) { nearDelta(1e-3, 600); }
TEST(HardRender, NearDeltaGaussian1e5) { nearDelta(1e-5, 601); }

// Sensor and light 1 m apart at height h0 = 5e-4 m over the plane: the shortest path via the plane
// is sqrt(1 + 4 h0^2) = 1 + 5e-7. A gaussian gate mu = 1 + 1e-6, sigma = 1e-6 draws ellipsoids from
// the focal distance itself (rejected: no path) through ones 1e-7..1e-5 longer than it, whose cut
// with the plane is a sliver ellipse 1e-3 wide. The reference evaluates the response at float32
// lengths, as the renderer must (test_scenes.h); intensity 1e10 keeps the value near 0.4.
TEST(HardRender, EllipsoidBarelyLongerThanFocalDistance) {
  const float h0 = 5e-4f, mu = float(1.0 + 1e-6), sigma = 1e-6f;
  const SeparatedPlane plane{1.0, h0, 0.75, 0.01, kRho, 1e10};
  Scene scene = separatedPlaneScene(plane.d, h0, plane.halfX, plane.halfY, kRho, plane.intensity);
  scene.render.spp = 20000;
  scene.render.seed = 610;
  scene.gate = gaussianGate(mu, sigma);
  double reference = separatedPlaneGaussianFloat(plane, mu, sigma);
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference, "ellipsoid 1e-6 longer than its foci");
}

// Confocal plane, box [2h - w, 2h + w] with w = 2e-3 h: the sphere of lengths s touches the plane at
// s = 2h (tangent, |P_T grad L| -> 0 at the touching point) and the lower half of the gate has no
// paths at all. Closed form (2/5) rho I h^3 (h^-5 - (h + w/2)^-5).
TEST(HardRender, EllipsoidTangentToSurface) {
  const double h = 1.0, w = 2e-3;
  Scene scene = confocalPlaneScene(h, 2.0, 2.0, kRho, 1.0);
  scene.gate.type = GateType::Box;
  scene.gate.a = 2 * h - w;
  scene.gate.b = 2 * h + w;
  double reference = confocalBox(h, kRho, 1.0, 2 * h - w, 2 * h + w);
  scene.render.spp = 20000;
  scene.render.seed = 620;
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference, "tangent ellipsoid");
  // Standard NEE reaches the gate only from directions within 2.6 degrees of the normal (1 in 500).
  scene.render.spp = 400000;
  scene.render.seed = 621;
  expectPointSensor(scene, NeeMode::Standard, reference, "tangent ellipsoid");
}

// The confocal plane at h = 1e-3 and 1e3 with every length scaled by h: gates box [2.1 h, 2.6 h]
// and gaussian (2.4 h, 0.1 h). With I = h^2 the response (proportional to I / h^2) is that of h = 1.
void scaled(double h, uint32_t seed) {
  Scene scene = confocalPlaneScene(h, 2.0 * h, 2.0 * h, kRho, h * h);
  scene.render.seed = seed;
  scene.gate.type = GateType::Box;
  scene.gate.a = 2.1 * h;
  scene.gate.b = 2.6 * h;
  double box = confocalBox(1.0, kRho, 1.0, 2.1, 2.6);
  scene.render.spp = 50000;
  expectPointSensor(scene, NeeMode::Standard, box, h < 1 ? "h = 1e-3, box" : "h = 1e3, box");
  scene.render.spp = 10000;
  expectPointSensor(scene, NeeMode::Ellipsoidal, box, h < 1 ? "h = 1e-3, box" : "h = 1e3, box");
  scene.gate = gaussianGate(2.4 * h, 0.1 * h);
  double gauss = confocalGated(
      1.0, kRho, 1.0, [](double l) { return gaussianWeight(l, 2.4, 0.1); }, 2.4 - kGaussianCutoff * 0.1,
      2.4 + kGaussianCutoff * 0.1);
  scene.render.spp = 50000;
  expectPointSensor(scene, NeeMode::Standard, gauss, h < 1 ? "h = 1e-3, gaussian" : "h = 1e3, gaussian");
  scene.render.spp = 10000;
  expectPointSensor(scene, NeeMode::Ellipsoidal, gauss, h < 1 ? "h = 1e-3, gaussian" : "h = 1e3, gaussian");
}

TEST(HardRender, TinySceneScale) { scaled(1e-3, 630); }
TEST(HardRender, HugeSceneScale) { scaled(1e3, 640); }

// Grazing: sensor and light 1 m apart only h0 = 1e-3 m above the plane, the sensor looking along
// the plane (normal (1, 0, -0.02)): light arrives at cos 2e-3..1e-2 and leaves toward the sensor
// likewise. The plane |x| <= 0.25 stops well short of the feet of sensor and light: there
// f ~ 1/|x-B|^3 would put a share of the response that the sensor's cosine sampling almost never
// finds (a heavy tail whose measured standard error is meaningless); on |x| <= 0.25 the ratio of
// f to that sampling density varies by (0.75/0.25)^3 = 27 at most. The gate
// [1.0002, 1.01] excludes the direct path (length 1) and keeps the paths via the plane.
TEST(HardRender, GrazingLightAndSensor) {
  const float h0 = 1e-3f;
  const glm::vec3 normal = glm::normalize(glm::vec3(1.0f, 0.0f, -0.02f));
  const SeparatedPlane plane{1.0, h0, 0.25, 0.1, kRho, 1e5, glm::dvec3(normal)};
  Scene scene = separatedPlaneScene(plane.d, h0, plane.halfX, plane.halfY, kRho, plane.intensity, normal);
  scene.gate.type = GateType::Box;
  scene.gate.a = 1.0002;
  scene.gate.b = 1.01;
  double reference = separatedPlaneGated(
      plane, [](double u) { return u >= 1.0002 && u <= 1.01 ? 1.0 : 0.0; }, 1.0002, 1.01);
  scene.render.spp = 4000000;
  scene.render.seed = 650;
  expectPointSensor(scene, NeeMode::Standard, reference, "grazing");
  scene.render.spp = 50000;
  scene.render.seed = 651;
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference, "grazing");
}

}  // namespace
}  // namespace vktg::test

namespace vktg::test {

// Degenerate geometry beside the confocal plane: a triangle whose vertices coincide, a collinear
// sliver and a 1e-7 m triangle, all in the plane's surface and in the gate's reach. Zero-area
// triangles can never be hit, sampled or met by an ellipsoid, and the tiny one covers 1e-14 m^2:
// the response must stay the plane's, finite, with both estimators (the ellipsoid query clips
// conics against every one of them).
TEST(HardRender, DegenerateAndTinyTriangles) {
  const double h = 1.0, a = 2.2, b = 2.6;
  Scene scene = confocalPlaneScene(h, 2.0, 2.0, kRho, 1.0);
  scene.gate.type = GateType::Box;
  scene.gate.a = a;
  scene.gate.b = b;
  Shape debris;
  debris.name = "debris";
  debris.material = scene.shapes.at(0).material;
  glm::vec3 p(0.4f, 0.3f, 0.0f);
  debris.positions = {p, p, p,                                                        // coincident
                      {0.5f, 0.0f, 0.0f}, {0.6f, 0.0f, 0.0f}, {0.7f, 0.0f, 0.0f},     // collinear
                      {0.45f, 0.45f, 0.0f}, {0.45f + 1e-7f, 0.45f, 0.0f}, {0.45f, 0.45f + 1e-7f, 0.0f}};
  debris.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  scene.shapes.push_back(debris);
  double reference = confocalBox(h, kRho, 1.0, a, b);
  scene.render.spp = 20000;
  scene.render.seed = 650;
  expectPointSensor(scene, NeeMode::Ellipsoidal, reference, "degenerate triangles");
  scene.render.spp = 100000;
  scene.render.seed = 651;
  expectPointSensor(scene, NeeMode::Standard, reference, "degenerate triangles");
}

}  // namespace vktg::test
