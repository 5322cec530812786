// The variance a render reports is the variance of its mean: every z-test in the suite divides by
// it, so an inflated one would make them all lenient and a deflated one would make them fail at
// random. Checked against the scatter of the means of independent seeds, per pixel, for the image
// and a derivative lane of a per-pixel render, and for the two splatted estimators (the edge term
// and the path-length-boundary connections from the camera), whose samples land in whichever pixel
// their camera connection reaches and whose variance resolve computes over all the render's samples.
//
// Per pixel p: s2_p is the sample variance of the S seeds' means and v_p the mean of their reported
// variances. Both are unbiased estimates of the variance of one seed's mean, so d_p = s2_p - v_p
// has expectation 0. Pixels are weighted by w_p = 1 / u_p, u_p the variance a separate pilot render
// (other seeds) reports (floored at 1/100 of its median), so that each pixel counts about equally; the weights are independent of
// the seeds' renders, which keeps the weighted ratio sum(w s2) / sum(w v) unbiased. (Per-pixel
// ratios s2_p / v_p would be biased low: a seed with an outlier raises its mean and its variance
// together.) The pixels' paths are independent, so sum(w d) has variance sum(w^2 Var d_p),
// estimated without bias by sum(w^2 d_p^2): the tolerance comes from the same renders and includes
// the heavy tails of path contributions, which a normal-theory bound on s2 would miss.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "grad/gradient.h"
#include "support/render_test.h"
#include "support/test_scenes.h"
#include "vktg/gate.h"
#include "vktg/parameters.h"
#include "vktg/scene.h"

namespace vktg::test {
namespace {

constexpr uint32_t kSeeds = 16;
constexpr uint32_t kFirstSeed = 1000;
constexpr double kZ = 4.0;  // two-sided alpha 6e-5 per channel
constexpr double kWeightRange = 100.0;

struct Ratio {
  double mean = 0, standardError = 0;  // sum(s2) / sum(v) and its standard error
  size_t pixels = 0;
};

// means[s], variances[s]: seed s's per-pixel values; pilot: the pilot render's variances.
Ratio scatterOverReported(const std::vector<std::vector<float>>& means, const std::vector<std::vector<float>>& variances,
                          const std::vector<float>& pilot) {
  double scatterSum = 0, reportedSum = 0, differenceSquares = 0;
  // A splatted estimator's pilot reports tiny variances where it reached a pixel once or twice;
  // weighting by their inverse would let those pixels (where a single sample makes scatter and
  // reported variance equal by construction) decide alone. The floor keeps every pixel's weight
  // within kWeightRange of the median's, and depends on the pilot only.
  std::vector<float> positive;
  for (float u : pilot)
    if (u > 0) positive.push_back(u);
  if (positive.empty()) return {};
  std::nth_element(positive.begin(), positive.begin() + positive.size() / 2, positive.end());
  const double floor = positive[positive.size() / 2] / kWeightRange;
  Ratio r;
  for (size_t i = 0; i < means[0].size(); ++i) {
    double sum = 0, reported = 0;
    for (size_t s = 0; s < kSeeds; ++s) sum += means[s][i], reported += variances[s][i];
    reported /= kSeeds;
    if (!(pilot[i] > 0)) continue;
    const double weight = 1.0 / std::max(double(pilot[i]), floor), mean = sum / kSeeds;
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

// `stratified`: the estimator's samples are stratified within a render (the edge pass's strategies
// in fixed proportions by blocks of samples, the camera connections' stratified ellipsoid
// positions), so the variance a render reports from its samples as if they were independent is an
// upper bound: the scatter may be smaller, never larger, and no more than 1.5x smaller (a bound so
// loose would make the z-tests that divide by it blind).
void expectReportedVarianceMatchesScatter(const Ratio& r, const char* what, bool stratified = false) {
  std::printf("  %s: scatter of %u seeds / reported variance = %.3f +- %.3f over %zu pixels\n", what, kSeeds, r.mean,
              r.standardError, r.pixels);
  ASSERT_GE(r.pixels, 50u) << what << ": too few lit pixels to test";
  if (stratified) {
    EXPECT_LT(r.mean - 1.0, kZ * r.standardError) << what << ": the reported variance is too small";
    EXPECT_GT(r.mean, 2.0 / 3.0) << what << ": the reported variance is over 1.5x the scatter";
  } else {
    EXPECT_LT(std::abs(r.mean - 1.0), kZ * r.standardError) << what;
  }
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

// One splatted term of `parameter` (the estimate and its reported variance), alone in the render.
struct SplattedTerm {
  std::vector<float> mean, variance;
};
SplattedTerm splattedTerm(const Scene& scene, const std::string& parameter, bool edges, uint32_t samplesPerPixel) {
  GradientOptions options;
  options.interior = false;
  options.edges = edges;
  options.pathLength = !edges;
  options.pathLengthPerPixel = false;
  options.pathLengthFromCamera = true;
  options.sppEdge = options.sppBoundaryCamera = samplesPerPixel;
  options.antithetic = AntitheticMode::Off;
  GradientResult g = renderGradient(testRenderer(), scene, {parameter}, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  const TermImages& term = edges ? g.edges : g.pathLength;
  EXPECT_EQ(edges ? g.plan.edges : g.plan.pathLengthFromCamera, true);
  EXPECT_FALSE(g.plan.interior || (edges ? g.plan.pathLength : g.plan.edges || g.plan.pathLengthPerPixel));
  return {term.derivatives.at(0).layers.at(0).pixels, term.variances.at(0).layers.at(0).pixels};
}

void expectSplattedVarianceMatchesScatter(Scene scene, const std::string& parameter, bool edges, uint32_t samplesPerPixel,
                                          const char* what) {
  scene.render.seed = 999;
  const SplattedTerm pilot = splattedTerm(scene, parameter, edges, 16 * samplesPerPixel);
  std::vector<std::vector<float>> means, variances;
  for (uint32_t s = 0; s < kSeeds; ++s) {
    scene.render.seed = kFirstSeed + s;
    SplattedTerm t = splattedTerm(scene, parameter, edges, samplesPerPixel);
    means.push_back(t.mean);
    variances.push_back(t.variance);
  }
  expectReportedVarianceMatchesScatter(scatterOverReported(means, variances, pilot.variance), what, true);
}

// The moving occluder's shadow on the floor (scenes/occluder_shadow.json at 16 x 16): its edges
// seen through the floor, and under a box gate the jumps of the camera -> floor -> light paths.
Scene occluderShadow() {
  Scene scene = loadScene(std::string(VKTG_SOURCE_DIR) + "/scenes/occluder_shadow.json");
  scene.camera.width = scene.camera.height = 16;
  return scene;
}

TEST(RenderVariance, EdgeTermVarianceMatchesTheScatterOfSeeds) {
  expectSplattedVarianceMatchesScatter(occluderShadow(), "occluder_x", true, 64, "edge term d / d occluder_x");
}

TEST(RenderVariance, CameraConnectionVarianceMatchesTheScatterOfSeeds) {
  Scene scene = occluderShadow();
  scene.gate = parseGateSpec("box:5.8,6.8");
  expectSplattedVarianceMatchesScatter(scene, "t0", false, 16, "path-length boundary from the camera d / d t0");
}

}  // namespace
}  // namespace vktg::test
