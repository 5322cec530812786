// Self-consistency of the renderer (DESIGN.md §5): box gates tiling every path length sum to the
// steady image; a transient stack summed over its bins is the steady image; steady rendering
// matches an independent brute-force CPU path tracer; ellipsoidal NEE and MIS agree with standard
// NEE on the same gate. Renders being compared use different seeds (independent), and every
// comparison is a per-pixel z-test (alpha 1e-3, Sidak over pixels) plus a z-test of the image means.
#include <gtest/gtest.h>

#include <cmath>

#include "support/cpu_path_tracer.h"
#include "support/render_test.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

constexpr double kZ = 3.29;  // two-sided alpha 1e-3 for the single image-mean test
// At most one pixel in this many may be lit in one image only (zTest cannot test those).
constexpr size_t kMaxHalfTestedFraction = 20;

const std::vector<float>& pixelsOf(const ImageSet& set, size_t layer = 0) { return set.layers.at(layer).pixels; }

RenderResult render(const Scene& scene, NeeMode nee) {
  RenderOptions options;
  options.nee = nee;
  RenderResult r = renderInTest(scene, options);
  EXPECT_EQ(r.stats.nonFinite, 0u);
  return r;
}

// Per-pixel z-test and image-mean test of a against b (variances of the means).
void expectSameImage(const std::vector<float>& a, const std::vector<float>& aVar, const std::vector<float>& b,
                     const std::vector<float>& bVar, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  ZTestResult z = zTest(a, aVar, b, bVar);
  EXPECT_EQ(z.rejected, 0u) << what << ": " << z.rejected << " of " << z.tested << " pixels differ; worst " << z.worst;
  // Pixels one side never saw lit are untested: they must stay the exception.
  EXPECT_LE(z.untestable, a.size() / kMaxHalfTestedFraction) << what << ": " << z.untestable << " of " << a.size()
                                                              << " pixels lit on one side only";
  ImageMean ma = imageMean(a, aVar), mb = imageMean(b, bVar);
  double se = std::hypot(ma.standardError, mb.standardError);
  EXPECT_GT(se, 0.0) << what;
  EXPECT_LT(std::abs(ma.mean - mb.mean), kZ * se)
      << what << ": image means " << ma.mean << " vs " << mb.mean << " (z = " << std::abs(ma.mean - mb.mean) / se << ")";
  std::printf("  %s: means %.6g vs %.6g (z = %.2f), worst pixel z %s, %zu pixels lit on one side only\n",
              what.c_str(), ma.mean, mb.mean, std::abs(ma.mean - mb.mean) / se, z.worst.c_str(), z.untestable);
}

// Paths of at most maxDepth + 1 segments (the last one a light connection) stay inside the scene's
// bounds, so no path is longer than (maxDepth + 1) * diagonal.
double longestPath(const Scene& scene) { return (scene.render.maxDepth + 1) * sceneDiagonal(scene) * 1.001; }

Scene smallCornell(uint32_t resolution, uint32_t spp, uint32_t seed) {
  Scene scene = cornellScene(resolution, 6.0, 0.0, false);
  scene.render.maxDepth = 3;
  scene.render.rouletteDepth = 2;
  scene.render.spp = spp;
  scene.render.seed = seed;
  return scene;
}

TEST(RenderConsistency, BoxGatesTileSteady) {
  Scene scene = smallCornell(16, 64, 100);
  RenderResult steady = render(scene, NeeMode::Standard);
  const double lMax = longestPath(scene);
  const int gates = 4;
  std::vector<float> sum(pixelsOf(steady.mean).size(), 0.0f), sumVar(sum.size(), 0.0f);
  for (int k = 0; k < gates; ++k) {
    Scene gated = scene;
    gated.gate.type = GateType::Box;
    gated.gate.a = lMax * k / gates;
    gated.gate.b = lMax * (k + 1) / gates;
    gated.render.seed = 101 + k;
    RenderResult r = render(gated, NeeMode::Standard);
    for (size_t i = 0; i < sum.size(); ++i) {
      sum[i] += pixelsOf(r.mean)[i];
      sumVar[i] += pixelsOf(r.variance)[i];
    }
  }
  expectSameImage(sum, sumVar, pixelsOf(steady.mean), pixelsOf(steady.variance), "sum of 4 box gates vs steady");
}

TEST(RenderConsistency, TransientStackSumsToSteady) {
  Scene scene = smallCornell(16, 64, 200);
  RenderResult steady = render(scene, NeeMode::Standard);
  Scene stack = scene;
  stack.gate.type = GateType::Bins;
  stack.gate.binStart = 0.0;
  stack.gate.binCount = 8;
  stack.gate.binWidth = longestPath(scene) / 8;
  stack.render.seed = 201;
  RenderResult r = render(stack, NeeMode::Standard);
  ASSERT_EQ(r.mean.layers.size(), 8u);
  // The bins of one render share paths, so their errors are correlated: bound the standard error
  // of the sum by the sum of the bins' standard errors (Cauchy-Schwarz).
  std::vector<float> sum(pixelsOf(steady.mean).size(), 0.0f), sumSd(sum.size(), 0.0f), sumVar(sum.size());
  for (size_t k = 0; k < 8; ++k)
    for (size_t i = 0; i < sum.size(); ++i) {
      sum[i] += pixelsOf(r.mean, k)[i];
      sumSd[i] += std::sqrt(pixelsOf(r.variance, k)[i]);
    }
  for (size_t i = 0; i < sum.size(); ++i) sumVar[i] = sumSd[i] * sumSd[i];
  expectSameImage(sum, sumVar, pixelsOf(steady.mean), pixelsOf(steady.variance), "sum of 8 bins vs steady");
}

// Steady GPU rendering against the CPU brute-force tracer with paths of at most maxDepth segments.
void expectMatchesCpu(uint32_t maxDepth, uint32_t gpuSpp, uint32_t cpuSpp, uint32_t seed) {
  Scene scene = cornellScene(12, 6.0, 0.0, false);
  scene.render.maxDepth = maxDepth;
  scene.render.spp = gpuSpp;
  scene.render.seed = seed;
  RenderResult gpu = render(scene, NeeMode::Standard);
  CpuRenderResult cpu = cpuPathTrace(scene, cpuSpp, maxDepth, seed);
  std::vector<float> cpuMean(cpu.mean.begin(), cpu.mean.end()), cpuVar(cpu.variance.begin(), cpu.variance.end());
  expectSameImage(pixelsOf(gpu.mean), pixelsOf(gpu.variance), cpuMean, cpuVar,
                  "steady GPU vs CPU tracer, max depth " + std::to_string(maxDepth));
}

// maxDepth 16: the series is converged (albedo <= 0.7, 0.7^16 ~ 3e-3 of what is left), so how the
// last depth is counted cannot matter; roulette on the GPU, none on the CPU.
TEST(RenderConsistency, SteadyMatchesCpuTracer) { expectMatchesCpu(16, 256, 2048, 300); }

// maxDepth 2: paths of at most two segments (direct light and one bounce); the truncation is
// a large part of the image, so counting a third segment (or dropping the second) fails.
TEST(RenderConsistency, SteadyMatchesCpuTracerShallow) { expectMatchesCpu(2, 256, 2048, 310); }

// Ellipsoidal (or MIS: BSDF-sampled and ellipsoidal vertices weighted by the power heuristic) vs
// standard NEE on one gate. maxDepth stays 16: the gate, not the depth, bounds the paths that
// matter, so both estimators integrate the same set of paths.
void expectNeeModesAgree(Scene scene, const std::string& what, NeeMode mode = NeeMode::Ellipsoidal) {
  RenderResult standard = render(scene, NeeMode::Standard);
  scene.render.seed += 1000;
  RenderResult other = render(scene, mode);
  EXPECT_EQ(other.plan.nee, mode);
  EXPECT_GT(other.stats.ellipsoidQueries, 0u);
  expectSameImage(pixelsOf(other.mean), pixelsOf(other.variance), pixelsOf(standard.mean), pixelsOf(standard.variance),
                  what);
}

Scene sensorCornell(uint32_t spp, uint32_t seed) {
  // Area light and point light: both light types go through both estimators.
  Scene scene = cornellScene(1, 6.0, 1.5, true);
  scene.render.spp = spp;
  scene.render.seed = seed;
  return scene;
}

TEST(RenderConsistency, NeeModesAgreePointSensorBox) {
  Scene scene = sensorCornell(100000, 400);
  scene.gate.type = GateType::Box;
  scene.gate.a = 3.0;
  scene.gate.b = 3.5;
  expectNeeModesAgree(scene, "point sensor, box [3, 3.5]: ellipsoidal vs standard");
}

TEST(RenderConsistency, NeeModesAgreePointSensorGaussian) {
  Scene scene = sensorCornell(100000, 410);
  scene.gate = gaussianGate(3.5, 0.2);
  expectNeeModesAgree(scene, "point sensor, gaussian (3.5, 0.2): ellipsoidal vs standard");
}

Scene perspectiveCornell(uint32_t spp, uint32_t seed) {
  Scene scene = cornellScene(12, 6.0, 1.5, false);
  scene.render.spp = spp;
  scene.render.seed = seed;
  return scene;
}

TEST(RenderConsistency, NeeModesAgreePerspectiveBox) {
  Scene scene = perspectiveCornell(256, 420);
  scene.gate.type = GateType::Box;
  scene.gate.a = 6.0;
  scene.gate.b = 6.6;
  expectNeeModesAgree(scene, "perspective, box [6, 6.6]: ellipsoidal vs standard");
}

TEST(RenderConsistency, NeeModesAgreePerspectiveGaussian) {
  Scene scene = perspectiveCornell(256, 430);
  scene.gate = gaussianGate(6.5, 0.25);
  expectNeeModesAgree(scene, "perspective, gaussian (6.5, 0.25): ellipsoidal vs standard");
}

// MIS where the gate holds direct light and indirect bounces (6 to 6.6 m in a 2 m room seen from
// 3.2 m, with an area and a point light): its weights must sum to one at every depth.
TEST(RenderConsistency, MisAgreesWithStandardNeePerspectiveBox) {
  Scene scene = perspectiveCornell(256, 440);
  scene.gate.type = GateType::Box;
  scene.gate.a = 6.0;
  scene.gate.b = 6.6;
  expectNeeModesAgree(scene, "perspective, box [6, 6.6]: MIS vs standard", NeeMode::Mis);
}

}  // namespace
}  // namespace vktg::test
