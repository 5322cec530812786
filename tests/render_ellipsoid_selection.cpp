// Renders with ellipsoidal NEE whose connections choose their triangle by the stochastic BVH descent
// (the planner's choice) agree with the exact answer and with the enumeration it replaced:
//  - the confocal plane tessellated into 2048 triangles against its closed form (the surface is the
//    same plane, only the tree is deep);
//  - the Cornell room, descent against enumeration pixel by pixel (z-test with both renders'
//    measured standard errors) and in the image mean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/render_test.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

RenderResult renderWith(const Scene& scene, EllipsoidSelection selection) {
  RenderOptions options;
  options.nee = NeeMode::Ellipsoidal;
  options.ellipsoidSelection = selection;
  RenderResult r = renderInTest(scene, options);
  EXPECT_EQ(r.stats.nonFinite, 0u);
  EXPECT_EQ(r.plan.ellipsoidSelection, selection);
  return r;
}

TEST(RenderEllipsoidSelection, TessellatedConfocalPlaneMatchesClosedForm) {
  const double h = 1.0, rho = 0.6, intensity = 1.0;
  Scene scene = confocalPlaneScene(h, 2.0, 2.0, rho, intensity);
  subdivideShape(scene.shapes[0], 5);
  ASSERT_EQ(scene.shapes[0].triangles.size(), 2048u);
  scene.gate = gaussianGate(2.4, 0.01);  // sigma / mu 4e-3: a near-delta gate
  scene.render.spp = 50000;
  scene.render.seed = 5;
  double lo = 2.4 - kGaussianCutoff * 0.01, hi = 2.4 + kGaussianCutoff * 0.01;
  double reference = confocalGated(h, rho, intensity, [](double l) { return gaussianWeight(l, 2.4, 0.01); }, lo, hi);
  RenderResult r = renderWith(scene, EllipsoidSelection::Descend);
  const float mean = r.mean.layers[0].pixels[0], variance = r.variance.layers[0].pixels[0];
  ASSERT_GT(variance, 0.0f);
  ZTestResult z = zTest({mean}, {variance}, {float(reference)}, {0.0f});
  EXPECT_EQ(z.rejected, 0u) << "expected " << reference << ": " << z.worst;
  std::printf("descent on 2048 triangles: %.6g (reference %.6g, relative se %.3g, %.2f s)\n", mean, reference,
              std::sqrt(variance) / reference, r.stats.seconds);
}

TEST(RenderEllipsoidSelection, CornellRoomDescentMatchesEnumeration) {
  Scene scene = cornellScene(16, 8.0, 0.0, false);
  // Paths around 8 m: three bounces and more, all of them ellipsoidal connections.
  scene.gate = gaussianGate(8.0, 0.08);
  scene.render.spp = 1024;
  scene.render.seed = 9;
  RenderResult descend = renderWith(scene, EllipsoidSelection::Descend);
  scene.render.seed = 10;
  RenderResult enumerate = renderWith(scene, EllipsoidSelection::Enumerate);
  const auto &a = descend.mean.layers[0].pixels, &av = descend.variance.layers[0].pixels;
  const auto &b = enumerate.mean.layers[0].pixels, &bv = enumerate.variance.layers[0].pixels;
  ZTestResult z = zTest(a, av, b, bv);
  EXPECT_EQ(z.rejected, 0u) << z.worst;
  EXPECT_GT(z.tested, a.size() / 2);
  ImageMean ma = imageMean(a, av), mb = imageMean(b, bv);
  double se = std::hypot(ma.standardError, mb.standardError);
  EXPECT_GT(ma.mean, 0.0);
  EXPECT_NEAR(ma.mean, mb.mean, 4.0 * se) << "image means differ";
  std::printf("image mean: descent %.6g +- %.3g (%.2f s), enumeration %.6g +- %.3g (%.2f s)\n", ma.mean,
              ma.standardError, descend.stats.seconds, mb.mean, mb.standardError, enumerate.stats.seconds);
}

}  // namespace
}  // namespace vktg::test
