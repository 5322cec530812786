// Chained interior passes (AdjointChain): the interior term of a loss gradient in several renders,
// each weighted by the adjoint image of the images rendered before it and adding its own paths'
// values to them.
// - An adjoint interior pass asked for its image renders, sample for sample, the image of a plain
//   render with the same seed and samples, also for views rendered together: the same bits on
//   lavapipe, and within float rounding on a GPU, whose compiler contracts the adjoint pipeline's
//   arithmetic differently from the render's (docs/precision.md).
// - For the loss sum (I - T)^2 over the pixels, the chained gradient and the gradient weighted by
//   an independent render's adjoint estimate the same derivative without bias: their means over
//   independent seeds agree within 4 combined standard errors measured from the seeds' spread.
//   Weighting a pass by an image that includes its own paths (what the chain must never do) moves
//   the mean by 2 sum Cov(I, dI/dθ); the test's images are noisy enough (one sample per pixel and
//   pass) for that to lie far outside the tolerance, which `biased` checks.
// - Adjoint images written between the passes reach the device through staging memory as they do
//   through mapped memory: the same gradient bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "grad/gradient.h"
#include "opt/loss.h"
#include "support/render_test.h"
#include "support/room_scene.h"
#include "support/scoped_env.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

// The interior term alone: the chain concerns it, and the other terms' passes are unchanged by it.
GradientOptions interiorOnly() {
  GradientOptions o;
  o.edges = false;
  o.pathLength = false;
  return o;
}

ImageSet zeroImage(const ImageSet& like) {
  ImageSet z = like;
  for (ImageLayer& l : z.layers) std::fill(l.pixels.begin(), l.pixels.end(), 0.0f);
  return z;
}

// The adjoint image of the L2 loss against T = 0 (opt/loss.h).
ImageSet lossAdjoint(const ImageSet& image) {
  ImageSet a;
  imageLoss(LossSpec{}, image, zeroImage(image), 1.0, &a);
  return a;
}

// The room with a gate that takes in its direct light, and 4 samples of 3 segments at most.
Scene chainScene() {
  Scene scene = test::roomScene();
  scene.gate = parseGateSpec("box:4.0,6.4");
  scene.render.spp = 4;
  scene.render.maxDepth = 3;
  return scene;
}

struct Fixture {
  explicit Fixture(Scene s = chainScene()) : scene(std::move(s)) {}
  const Scene scene;
  const std::vector<std::string> names = {"floor_albedo", "lamp_power"};
  const ParameterModel model{scene, {findParameter(scene, names[0]), findParameter(scene, names[1])}};
  const std::vector<double> theta = std::vector<double>(model.size(), 0.0);
  DeviceScene device{test::testRenderer().context(), model, theta, theta};

  RenderResult render(uint32_t seed, uint32_t spp) {
    RenderSetup setup = RenderSetup::of(scene);
    setup.settings.seed = seed;
    setup.settings.spp = spp;
    return test::testRenderer().render(device, setup, RenderOptions{});
  }
};

// Two views of the room (seeds 17 and 23) render together, one below the other (4.8): each view's
// image is its plain render's, sample for sample. A GPU compiles the adjoint pipeline's arithmetic
// apart from the render's and may contract its multiply-adds differently (docs/precision.md), so
// each pixel is held to kContractionUlps units of rounding (u = 2^-24) of its value: a path's value
// is a product of a few hundred operations at 1 u each, and the pixel a sum of such values. Any
// other difference (a sample missed, counted twice, weighted or seeded otherwise) moves a pixel by
// a whole path's share of it. The gate is a gaussian, not the fixture's box, so that an ulp of path
// length changes a path's weight by ulps too rather than taking it in or out.
TEST(GradAdjointChained, AnInteriorPassRendersThePlainRendersImage) {
  constexpr double kContractionUlps = 256;
  const double u = std::numeric_limits<float>::epsilon() / 2;
  Scene scene = chainScene();
  scene.gate = parseGateSpec("gaussian:5.2,0.6");
  Fixture f(scene);
  const std::vector<uint32_t> seeds = {17, 23};
  std::vector<ImageSet> plain, adjoints;
  AdjointChain chain;
  chain.passes = 1;
  chain.imageSpp = 0;  // the pass's own images are all there is
  chain.adjointOf = [](size_t, const ImageSet& image) { return lossAdjoint(image); };
  chain.seedOf = [&](size_t view, uint32_t) { return seeds[view]; };
  for (uint32_t seed : seeds) {
    plain.push_back(f.render(seed, 4).mean);
    adjoints.push_back(lossAdjoint(plain.back()));
    chain.images.push_back(zeroImage(plain.back()));
  }
  std::vector<AdjointView> views;
  for (size_t v = 0; v < seeds.size(); ++v) views.push_back({RenderSetup::of(f.scene), {}, &adjoints[v]});
  ASSERT_EQ(viewGroups(views, true).size(), 1u);
  AdjointState state;
  const LossGradient g = lossGradient(test::testRenderer(), f.device, views, interiorOnly(), state, &chain);
  ASSERT_EQ(g.images.size(), seeds.size());
  for (size_t v = 0; v < seeds.size(); ++v) {
    ASSERT_EQ(g.images[v].layers.size(), plain[v].layers.size());
    double sum = 0, worstUlps = 0;
    for (size_t l = 0; l < plain[v].layers.size(); ++l)
      for (size_t i = 0; i < plain[v].layers[l].pixels.size(); ++i) {
        const double chained = g.images[v].layers[l].pixels[i], expected = plain[v].layers[l].pixels[i];
        if (chained != expected) worstUlps = std::max(worstUlps, std::abs(chained - expected) / (u * std::abs(expected)));
        EXPECT_LE(std::abs(chained - expected), kContractionUlps * u * std::abs(expected))
            << "view " << v << " layer " << l << " pixel " << i;
        sum += expected;
      }
    EXPECT_GT(sum, 0.0);
    std::printf("  view %zu: largest difference from the plain render %.1f u\n", v, worstUlps);
  }
  EXPECT_NE(plain[0].layers[0].pixels, plain[1].layers[0].pixels);
}

// Each chained pass writes its adjoint image anew; where the device's memory is not mapped, the
// group's next render copies it from staging (VKTG_DEVICE_MEMORY=staged forces that on any device).
// The passes see the same images either way, so the gradient and the image are the same bit for bit.
TEST(GradAdjointChained, StagedDeviceMemoryGivesTheSameChainedGradient) {
  auto chainedGradient = [](AdjointState& state) {
    Renderer renderer(test::testRenderer().context());
    Fixture f;
    RenderSetup primal = RenderSetup::of(f.scene);
    primal.settings.spp = 1;
    const ImageSet image = renderer.render(f.device, primal, RenderOptions{}).mean;
    const ImageSet adjoint = lossAdjoint(image);
    AdjointView view{RenderSetup::of(f.scene), {}, &adjoint};
    view.setup.settings.seed = 29;
    AdjointChain chain;
    chain.passes = 4;
    chain.images = {image};
    chain.imageSpp = 1;
    chain.adjointOf = [](size_t, const ImageSet& soFar) { return lossAdjoint(soFar); };
    chain.seedOf = [](size_t, uint32_t pass) { return 31 + pass; };
    return lossGradient(renderer, f.device, {view}, GradientOptions{}, state, &chain);
  };
  AdjointState settled;
  chainedGradient(settled);
  AdjointState mappedState;
  mappedState.scale = settled.scale;
  const LossGradient mapped = chainedGradient(mappedState);
  test::ScopedEnv env("VKTG_DEVICE_MEMORY", "staged");
  AdjointState stagedState;
  stagedState.scale = settled.scale;
  const LossGradient staged = chainedGradient(stagedState);
  ASSERT_FALSE(stagedState.accumulator->buffer().hostReadable());
  ASSERT_EQ(mapped.attempts, 1u);
  ASSERT_EQ(staged.attempts, 1u);
  for (size_t k = 0; k < mapped.theta.size(); ++k) EXPECT_EQ(staged.theta[k], mapped.theta[k]) << k;
  EXPECT_NE(mapped.theta[0], 0.0);
  ASSERT_EQ(staged.images.size(), 1u);
  EXPECT_EQ(staged.images[0].layers[0].pixels, mapped.images[0].layers[0].pixels);
}

struct Estimate {
  std::vector<double> mean, standardError;
};

Estimate summarize(const std::vector<std::vector<double>>& runs) {
  Estimate e;
  const size_t n = runs.front().size(), seeds = runs.size();
  e.mean.assign(n, 0.0);
  e.standardError.assign(n, 0.0);
  for (const auto& r : runs)
    for (size_t k = 0; k < n; ++k) e.mean[k] += r[k] / double(seeds);
  for (const auto& r : runs)
    for (size_t k = 0; k < n; ++k) e.standardError[k] += (r[k] - e.mean[k]) * (r[k] - e.mean[k]) / double(seeds - 1);
  for (double& v : e.standardError) v = std::sqrt(v / double(seeds));
  return e;
}

// `seeds` gradients of sum I^2: the render at 1 spp, then the interior term at 4 spp, in 4 chained
// passes or (passes = 1) in one pass weighted by the render's adjoint alone. With `ownImage` the
// chain's adjoints include each pass's own image (its seeds' render, drawn ahead): biased on purpose.
Estimate gradients(Fixture& f, uint32_t passes, bool ownImage, uint32_t seeds) {
  std::vector<std::vector<double>> runs;
  AdjointState state;
  for (uint32_t s = 0; s < seeds; ++s) {
    const uint32_t base = 1000 + 7919 * s;
    const ImageSet image = f.render(base, 1).mean;
    const ImageSet adjoint = lossAdjoint(image);
    AdjointView view{RenderSetup::of(f.scene), {}, &adjoint};
    view.setup.settings.spp = 4;
    view.setup.settings.seed = base + 1;
    AdjointChain chain;
    chain.passes = passes;
    chain.images = {image};
    chain.imageSpp = 1;
    chain.seedOf = [&](size_t, uint32_t pass) { return base + 2 + pass; };
    // Interior passes only: an attempt asks for the adjoints of passes 1 … passes - 1, in order.
    uint32_t calls = 0;
    chain.adjointOf = [&](size_t, const ImageSet& soFar) {
      if (!ownImage) return lossAdjoint(soFar);
      // The image so far with the next pass's own paths (rendered alone: the same samples) merged in.
      const uint32_t pass = 1 + calls++ % (passes - 1);
      const ImageSet own = f.render(chain.seedOf(0, pass), 1).mean;
      ImageSet merged = soFar;
      for (size_t l = 0; l < merged.layers.size(); ++l)
        for (size_t i = 0; i < merged.layers[l].pixels.size(); ++i)
          merged.layers[l].pixels[i] = 0.5f * (merged.layers[l].pixels[i] + own.layers[l].pixels[i]);
      return lossAdjoint(merged);
    };
    const LossGradient g = lossGradient(test::testRenderer(), f.device, {view}, interiorOnly(), state, passes > 1 ? &chain : nullptr);
    EXPECT_EQ(g.stats.nonFinite, 0u);
    if (passes > 1) EXPECT_EQ(g.images.size(), 1u);
    runs.push_back(g.theta);
  }
  return summarize(runs);
}

TEST(GradAdjointChained, ChainedPassesAgreeWithAnIndependentRendersAdjoint) {
  Fixture f;
  constexpr uint32_t kSeeds = 48;
  const Estimate independent = gradients(f, 1, false, kSeeds);
  const Estimate chained = gradients(f, 4, false, kSeeds);
  const Estimate biased = gradients(f, 4, true, kSeeds);
  for (size_t k = 0; k < f.model.size(); ++k) {
    const double se = std::hypot(chained.standardError[k], independent.standardError[k]);
    std::printf("  %s: independent %+.5e (se %.2e), chained %+.5e (se %.2e), own image %+.5e (se %.2e)\n",
                f.names[k].c_str(), independent.mean[k], independent.standardError[k], chained.mean[k],
                chained.standardError[k], biased.mean[k], biased.standardError[k]);
    EXPECT_NEAR(chained.mean[k], independent.mean[k], 4 * se) << f.names[k];
    EXPECT_GT(std::abs(independent.mean[k]), 6 * se) << "too noisy to test";
    const double biasedSe = std::hypot(biased.standardError[k], independent.standardError[k]);
    EXPECT_GT(std::abs(biased.mean[k] - independent.mean[k]), 4 * biasedSe) << "the test cannot see a pass's own image";
  }
}

}  // namespace
}  // namespace vktg
