// Stratified boundary samples (docs/theory.md 3.7): the edge samples and the camera's connections
// draw their main choice from one randomly shifted sequence per render instead of independent
// numbers. Each sample alone is still uniform, so the loss gradient keeps its expected value; the
// samples of a gradient spread evenly along the edges and along the curves the gate's jumps cut
// from the scene, so its variance falls. Both are measured here over independent seeds, on a
// heightfield seen from above with a point light beside the camera and a box gate around the direct
// returns (the setting of `vktg bench optimize`, where the term pilot saw the edges' variance fall
// 12× and the camera connections' about 1000×).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "grad/gradient.h"
#include "support/grad_test.h"
#include "support/render_test.h"
#include "support/scoped_env.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

Scene heightfieldScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 2.2, 0.3], "look_at": [0, 0, 0], "fov_y": 50,
               "resolution": [24, 24]},
    "gate": {"type": "box", "a": 4.55, "b": 4.85},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.7}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [5, 5], "size": [2, 2], "material": "ground",
       "heights": [0, 0.05, 0.1, 0.05, 0, 0.05, 0.2, 0.25, 0.1, 0, 0.1, 0.25, 0.35, 0.2, 0.05,
                   0.05, 0.15, 0.2, 0.1, 0, 0, 0.05, 0.05, 0, 0]}
    ],
    "lights": [{"type": "point", "name": "laser", "position": [0.25, 2.2, 0.3], "intensity": 3}],
    "parameters": [{"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"}],
    "render": {"spp": 8, "max_depth": 2, "seed": 1}
  })", "stratified.json", ".");
}

// Per parameter, the mean of the gradients of `seeds` seeds and the variance of one.
struct SeedStatistics {
  std::vector<double> mean, variance;
};

SeedStatistics gradientsOverSeeds(const char* samples, bool edges, uint32_t seeds) {
  test::ScopedEnv env("VKTG_BOUNDARY_SAMPLES", samples);
  const Scene scene = heightfieldScene();
  std::vector<uint32_t> indices(scene.parameters.size());
  for (uint32_t k = 0; k < indices.size(); ++k) indices[k] = k;
  const ParameterModel model(scene, indices);
  const std::vector<double> theta(model.size(), 0.0);
  DeviceScene device(test::testRenderer().context(), model, theta, theta);
  const ImageSet adjoint = test::randomAdjointImage(scene.camera.width, scene.camera.height, scene.gate.layers(), 3);
  AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  GradientOptions options;
  options.interior = false;
  options.edges = edges;
  options.pathLength = !edges;
  options.pathLengthPerPixel = false;  // its connections from path vertices draw independent numbers
  options.sppEdge = options.sppBoundary = 8;
  AdjointState state;
  SeedStatistics s{std::vector<double>(model.size(), 0.0), std::vector<double>(model.size(), 0.0)};
  std::vector<std::vector<double>> all;
  for (uint32_t seed = 0; seed < seeds; ++seed) {
    view.setup.settings.seed = 100 + seed;
    all.push_back(lossGradient(test::testRenderer(), device, {view}, options, state).theta);
  }
  for (size_t k = 0; k < model.size(); ++k) {
    for (const auto& g : all) s.mean[k] += g[k] / seeds;
    for (const auto& g : all) s.variance[k] += (g[k] - s.mean[k]) * (g[k] - s.mean[k]) / (seeds - 1);
  }
  return s;
}

void expectSameMeanLessVariance(bool edges) {
  const uint32_t seeds = 10;
  const SeedStatistics stratified = gradientsOverSeeds("stratified", edges, seeds);
  const SeedStatistics independent = gradientsOverSeeds("independent", edges, seeds);
  // Summed over the heights: the squared difference of the means against its expectation if both
  // are unbiased (the two variances of a mean), and the variances themselves.
  double squaredDifference = 0, expected = 0, varianceStratified = 0, varianceIndependent = 0, signal = 0;
  for (size_t k = 0; k < stratified.mean.size(); ++k) {
    const double d = stratified.mean[k] - independent.mean[k];
    squaredDifference += d * d;
    expected += (stratified.variance[k] + independent.variance[k]) / seeds;
    varianceStratified += stratified.variance[k];
    varianceIndependent += independent.variance[k];
    signal += independent.mean[k] * independent.mean[k];
  }
  std::printf("%s: squared difference of the means %.3g (%.3g expected), variance %.3g stratified, %.3g "
              "independent (%.2fx), squared mean %.3g\n",
              edges ? "edges" : "camera connections", squaredDifference, expected, varianceStratified,
              varianceIndependent, varianceStratified / varianceIndependent, signal);
  // A sum over 25 heights of (difference / its standard error)^2 has mean 1 relative to `expected`;
  // 4 leaves room for the variances' own error from 10 seeds. A bias of a few standard errors of the
  // independent mean fails it.
  EXPECT_LT(squaredDifference, 4.0 * expected);
  // The gradient must be well resolved for the comparison to mean anything.
  EXPECT_GT(signal, 20.0 * expected);
  // Measured 0.12x (edges) and 0.03x (camera connections) here; independent numbers give 1x,
  // whose estimate from 10 seeds is rarely below 0.5.
  EXPECT_LT(varianceStratified, 0.5 * varianceIndependent);
}

TEST(StratifiedBoundarySamples, EdgeTermKeepsItsMeanWithLessVariance) { expectSameMeanLessVariance(true); }

TEST(StratifiedBoundarySamples, CameraConnectionsKeepTheirMeanWithLessVariance) { expectSameMeanLessVariance(false); }

}  // namespace
}  // namespace vktg
