// The variance a render reports is the variance of its mean: every z-test in the suite divides by
// it, so an inflated one would make them all lenient and a deflated one would make them fail at
// random. Checked against the scatter of the means of independent seeds, per pixel, for the image
// and for a derivative lane.
//
// Per pixel p: s2_p is the sample variance of the S seeds' means and v_p the mean of their reported
// variances. Both are unbiased estimates of the variance of one seed's mean, so d_p = s2_p - v_p
// has expectation 0. Pixels are weighted by w_p = 1 / u_p, u_p the variance a separate pilot render
// (other seeds) reports, so that each pixel counts about equally; the weights are independent of
// the seeds' renders, which keeps the weighted ratio sum(w s2) / sum(w v) unbiased. (Per-pixel
// ratios s2_p / v_p would be biased low: a seed with an outlier raises its mean and its variance
// together.) The pixels' paths are independent, so sum(w d) has variance sum(w^2 Var d_p),
// estimated without bias by sum(w^2 d_p^2): the tolerance comes from the same renders and includes
// the heavy tails of path contributions, which a normal-theory bound on s2 would miss.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/render_test.h"
#include "support/test_scenes.h"
#include "vktg/gate.h"
#include "vktg/parameters.h"

namespace vktg::test {
namespace {

constexpr uint32_t kSeeds = 16;
constexpr uint32_t kFirstSeed = 1000;
constexpr double kZ = 4.0;  // two-sided alpha 6e-5 per channel

struct Ratio {
  double mean = 0, standardError = 0;  // sum(s2) / sum(v) and its standard error
  size_t pixels = 0;
};

// means[s], variances[s]: seed s's per-pixel values; pilot: the pilot render's variances.
Ratio scatterOverReported(const std::vector<std::vector<float>>& means, const std::vector<std::vector<float>>& variances,
                          const std::vector<float>& pilot) {
  double scatterSum = 0, reportedSum = 0, differenceSquares = 0;
  Ratio r;
  for (size_t i = 0; i < means[0].size(); ++i) {
    double sum = 0, reported = 0;
    for (size_t s = 0; s < kSeeds; ++s) sum += means[s][i], reported += variances[s][i];
    reported /= kSeeds;
    if (!(pilot[i] > 0)) continue;
    const double weight = 1.0 / pilot[i], mean = sum / kSeeds;
    double scatter = 0;
    for (size_t s = 0; s < kSeeds; ++s) scatter += (means[s][i] - mean) * (means[s][i] - mean);
    scatter /= kSeeds - 1;
    scatterSum += weight * scatter;
    reportedSum += weight * reported;
    differenceSquares += weight * weight * (scatter - reported) * (scatter - reported);
    r.pixels++;
  }
  if (reportedSum > 0) {
    r.mean = scatterSum / reportedSum;
    r.standardError = std::sqrt(differenceSquares) / reportedSum;
  }
  return r;
}

void expectReportedVarianceMatchesScatter(const Ratio& r, const char* what) {
  std::printf("  %s: scatter of %u seeds / reported variance = %.3f +- %.3f over %zu pixels\n", what, kSeeds, r.mean,
              r.standardError, r.pixels);
  ASSERT_GE(r.pixels, 50u) << what << ": too few lit pixels to test";
  EXPECT_LT(std::abs(r.mean - 1.0), kZ * r.standardError) << what;
  // Power: a variance reported 1.5x too large (ratio 2/3) or too small must not pass.
  EXPECT_LT(kZ * r.standardError, 1.0 / 3.0) << what << ": the check is too weak to see a 1.5x error";
}

TEST(RenderVariance, ReportedVarianceMatchesTheScatterOfSeeds) {
  Scene scene = cornellScene(12, 6.0, 2.0, false);
  scene.render.maxDepth = 3;
  scene.render.spp = 64;
  scene.gate = parseGateSpec("box:3.5,5.5");
  Parameter p;
  p.name = "white_albedo", p.kind = ParameterKind::Albedo, p.target = "white";
  scene.parameters.push_back(p);
  RenderOptions options;
  options.nee = NeeMode::Standard;
  options.derivativeLanes = bindParameters(scene, {"white_albedo"});
  Scene pilotScene = scene;
  pilotScene.render.seed = 999;
  pilotScene.render.spp = 16 * scene.render.spp;  // steady weights
  const RenderResult pilot = renderInTest(pilotScene, options);
  std::vector<std::vector<float>> image, imageVariance, derivative, derivativeVariance;
  for (uint32_t s = 0; s < kSeeds; ++s) {
    scene.render.seed = kFirstSeed + s;
    RenderResult r = renderInTest(scene, options);
    ASSERT_EQ(r.stats.nonFinite, 0u);
    image.push_back(r.mean.layers.at(0).pixels);
    imageVariance.push_back(r.variance.layers.at(0).pixels);
    derivative.push_back(r.derivatives.at(0).layers.at(0).pixels);
    derivativeVariance.push_back(r.derivativeVariances.at(0).layers.at(0).pixels);
  }
  expectReportedVarianceMatchesScatter(scatterOverReported(image, imageVariance, pilot.variance.layers.at(0).pixels),
                                       "image");
  expectReportedVarianceMatchesScatter(
      scatterOverReported(derivative, derivativeVariance, pilot.derivativeVariances.at(0).layers.at(0).pixels),
      "d image / d white albedo");
}

}  // namespace
}  // namespace vktg::test
