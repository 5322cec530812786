// Loss gradients with fewer samples than pixels (RenderOptions::samplesPerPixel, the term pilot's
// allocations below one sample per pixel): each term at a quarter of a sample per pixel, averaged
// over independent seeds, against the same term at whole samples per pixel. A per-pixel pass then
// starts its paths at a pixel the seed draws (without it every seed would cover the same rows) and
// weights them by 1 / (paths / pixels); a splatted pass just takes fewer samples. The tolerance is
// 4 combined standard errors measured from the seeds' spread, and each gradient is checked to be
// well above it, so that a wrong weight (1 / ceil(spp), a factor 4 here) or a fixed subset of
// pixels fails.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "grad/gradient.h"
#include "support/render_test.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

// A floor, a block over it and an area light, with a pinhole above: every term has work. The box
// gate's far end is beyond every path, so that the gate centre's derivative is its near jump's alone
// (two jumps would cancel in part). A jump at 4.2 m crosses the direct light (two segments, which
// the connections from the camera place), one at 5.2 m the light of a bounce (the per-pixel ones).
Scene floorScene(double gateStart) {
  Scene scene = parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.2, 3], "look_at": [0, 0.2, 0], "fov_y": 40, "resolution": [16, 16]},
    "gate": {"type": "box", "a": 4.2, "b": 30},
    "materials": {"floor": {"type": "diffuse", "albedo": 0.6}, "white": {"type": "diffuse", "albedo": 0.8}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "floor", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "block", "type": "cube", "material": "white",
       "transform": {"translate": [0.1, 0.45, 0], "rotate": [0, 25, 0], "scale": 0.25}},
      {"name": "lamp", "type": "rectangle", "emission": 8,
       "transform": {"translate": [0.3, 1.6, 0.2], "rotate": [90, 0, 0], "scale": 0.3}}
    ],
    "parameters": [
      {"name": "block_x", "type": "translate", "shape": "block", "axis": [1, 0, 0]},
      {"name": "t0", "type": "gate_center"}
    ],
    "render": {"spp": 4, "max_depth": 3, "seed": 3}
  })", "floor.json", ".");
  scene.gate.a = gateStart;
  return scene;
}

// An adjoint image whose lower half weighs three times its upper half, and its right half three
// times its left (so that the block's two sides do not cancel when it moves sideways): a pass that
// reached only some rows would move the gradient.
ImageSet rowAdjoint(uint32_t width, uint32_t height, uint32_t layers) {
  ImageSet a;
  a.width = width;
  a.height = height;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.5f, 1.0f);
  for (uint32_t l = 0; l < layers; ++l) {
    ImageLayer layer;
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) layer.pixels.push_back((y < height / 2 ? 1.0f : 3.0f) * (x < width / 2 ? 1.0f : 3.0f) * u(rng));
    a.layers.push_back(layer);
  }
  return a;
}

struct Estimate {
  std::vector<double> mean, standardError;
};

// The mean of `seeds` loss gradients of one term at `spp` samples per pixel, and its standard error.
Estimate termGradient(const Scene& scene, bool edges, bool perPixel, bool fromCamera, double spp, uint32_t seeds) {
  std::vector<uint32_t> all(scene.parameters.size());
  for (uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  ParameterModel model(scene, all);
  std::vector<double> theta(model.size(), 0.0);
  DeviceScene device(test::testRenderer().context(), model, theta, theta);
  const ImageSet adjoint = rowAdjoint(scene.camera.width, scene.camera.height, scene.gate.layers());
  GradientOptions o;
  o.interior = false;
  o.edges = edges;
  o.pathLength = perPixel || fromCamera;
  o.pathLengthPerPixel = perPixel;
  o.pathLengthFromCamera = fromCamera;
  o.sppEdge = o.sppBoundary = o.sppBoundaryCamera = spp;
  AdjointState state;
  std::vector<std::vector<double>> runs;
  for (uint32_t s = 0; s < seeds; ++s) {
    AdjointView view{RenderSetup::of(scene), {}, &adjoint};
    view.setup.settings.seed = 1000 + 7919 * s;
    LossGradient g = lossGradient(test::testRenderer(), device, {view}, o, state);
    EXPECT_EQ(g.stats.nonFinite, 0u);
    runs.push_back(g.theta);
  }
  Estimate e;
  const size_t n = runs.front().size();
  e.mean.assign(n, 0.0);
  e.standardError.assign(n, 0.0);
  for (const auto& r : runs)
    for (size_t k = 0; k < n; ++k) e.mean[k] += r[k] / seeds;
  for (const auto& r : runs)
    for (size_t k = 0; k < n; ++k) e.standardError[k] += (r[k] - e.mean[k]) * (r[k] - e.mean[k]) / (seeds - 1);
  for (double& v : e.standardError) v = std::sqrt(v / seeds);
  return e;
}

void expectFractionAgrees(bool edges, bool perPixel, bool fromCamera, double gateStart, size_t parameter, uint32_t seeds) {
  const Scene scene = floorScene(gateStart);
  // Equal work: 4 x `seeds` seeds of a quarter sample per pixel against `seeds` of one.
  const Estimate few = termGradient(scene, edges, perPixel, fromCamera, 0.25, 4 * seeds);
  const Estimate whole = termGradient(scene, edges, perPixel, fromCamera, 1.0, seeds);
  const double se = std::hypot(few.standardError[parameter], whole.standardError[parameter]);
  std::printf("  %s: 0.25 spp %+.5e (se %.2e), 1 spp %+.5e (se %.2e)\n", scene.parameters[parameter].name.c_str(),
              few.mean[parameter], few.standardError[parameter], whole.mean[parameter], whole.standardError[parameter]);
  EXPECT_NEAR(few.mean[parameter], whole.mean[parameter], 4 * se);
  // A quarter of the weight would be off by three quarters of the gradient: outside 4 se.
  EXPECT_GT(std::abs(whole.mean[parameter]), 6 * se) << "too noisy to test";
}

TEST(GradAdjointFractional, PerPixelPathLengthBoundarySpreadOverThePixels) { expectFractionAgrees(false, true, false, 5.2, 1, 160); }

TEST(GradAdjointFractional, CameraConnectionsAtAQuarterSamplePerPixel) { expectFractionAgrees(false, false, true, 4.2, 1, 16); }

TEST(GradAdjointFractional, EdgeSamplesAtAQuarterSamplePerPixel) { expectFractionAgrees(true, false, false, 4.2, 0, 128); }

}  // namespace
}  // namespace vktg
