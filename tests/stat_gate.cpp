// Statistical and element-wise tests of the GPU gate functions (shaders/lib/gate.glsl) through
// tests/shaders/gate_sample.comp, for gaussian (plain, normalised, and close to L = 0), box,
// truncated gaussian and bins gates:
//  1. gateSampleLength draws s from the density it claims: a chi-square test of the samples
//     against the analytic density, and per sample, the returned value equals 1 / that density.
//  2. It is an unbiased estimator of the gate's integral: mean(W(s) / p(s)) equals
//     Gate::integral() (src/scene/gate.cpp) within the measured standard error.
//  3. gateWeight and gateLayers on the GPU equal Gate::weight on the CPU over many lengths.
// Gate numbers are dyadic (exact in float) so that CPU and GPU decide boundaries identically;
// otherwise a length within one float ulp of an edge could legitimately fall on either side.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "support/chi2.h"
#include "support/gpu_test.h"
#include "support/test_gates.h"
#include "vktg/gate.h"

namespace vktg::test {
namespace {

struct GateIn {
  float u[2], length;
  uint32_t layer;
};
struct GateOut {
  float s, invPdf, weightAtS, weightAtLength;
  uint32_t first, count, pad[2];
};
static_assert(sizeof(GateIn) == 16 && sizeof(GateOut) == 32);

constexpr uint32_t kSamples = 1u << 18;
constexpr int kGateCases = 6;  // the chi-square tests below share one false-failure rate
// Two-sided normal quantile for 1e-4 per comparison of a mean with its expectation.
constexpr double kMeanZ = 3.89;

std::vector<GateCase> gateCases() {
  std::vector<GateCase> cases = representativeGates();
  // mu < 6.5 sigma: the sampler draws negative lengths, which no path has.
  cases.push_back({"gaussian_near_zero", gaussianGate(0.5, 0.25)});
  return cases;
}

// u in [0, 1) with 24 random bits, like the renderer's float random numbers.
float uniform01(std::mt19937& rng) { return float(rng() >> 8) * (1.0f / 16777216.0f); }

struct GateRun {
  std::vector<GateIn> in;
  std::vector<GateOut> out;
};

GateRun runGate(const Gate& gate, uint32_t seed) {
  GateRun run;
  std::mt19937 rng(seed);
  const double lo = gate.supportMin() - 1.0, hi = gate.supportMax() + 1.0;
  // Lengths for the element-wise comparison: the edges of every piece first, then uniform.
  std::vector<float> special;
  for (double j : gate.jumpLocations()) special.push_back(float(j));
  if (gate.type == GateType::Gaussian) {
    special.push_back(float(gate.mu));
    special.push_back(float(gate.mu + kGaussianCutoff * gate.sigma));
    special.push_back(float(gate.mu - kGaussianCutoff * gate.sigma));
  }
  run.in.resize(kSamples);
  for (uint32_t i = 0; i < kSamples; ++i) {
    GateIn& g = run.in[i];
    g.u[0] = uniform01(rng);
    g.u[1] = uniform01(rng);
    g.length = i < special.size() ? special[i] : float(lo + (hi - lo) * uniform01(rng));
    g.layer = gate.layers() > 1 ? rng() % gate.layers() : 0;
  }
  const Scene scene = sceneWithGate(gate);
  run.out = runKernel<GateOut>("gate_sample", run.in, kSamples, kSamples, &scene);
  return run;
}

// The density gateSampleLength claims: N(mu, sigma) for gaussians, uniform on the support else.
double claimedDensity(const Gate& gate, double s) {
  if (gate.type == GateType::Gaussian) {
    double z = (s - gate.mu) / gate.sigma;
    return std::exp(-0.5 * z * z) / (gate.sigma * std::sqrt(2 * std::numbers::pi));
  }
  return (s >= gate.supportMin() && s <= gate.supportMax()) ? 1.0 / (gate.supportMax() - gate.supportMin()) : 0.0;
}

class StatGate : public ::testing::TestWithParam<GateCase> {};

TEST_P(StatGate, SamplesFollowTheClaimedDensity) {
  const Gate& gate = GetParam().gate;
  GateRun run = runGate(gate, 1234);
  std::vector<double> samples;
  size_t badPdf = 0;
  std::string firstBad;
  for (const GateOut& o : run.out) {
    samples.push_back(o.s);
    // 1/p from the GPU against p in double at the same float s. For gaussians the relative error
    // is dominated by exp(z^2/2) with z^2/2 <= 17 (Box-Muller with 24-bit u reaches 5.8 sigma):
    // about 17 * 2^-22 from z^2 plus the exp's few ulps, below 1e-5.
    double relative = std::abs(double(o.invPdf) * claimedDensity(gate, o.s) - 1.0);
    if (!(relative < 2e-5)) {
      if (badPdf++ == 0) firstBad = "s = " + std::to_string(o.s) + ", 1/p = " + std::to_string(o.invPdf);
    }
  }
  EXPECT_EQ(badPdf, 0u) << "returned 1/p disagrees with the sampled density, first at " << firstBad;

  double lo = gate.supportMin(), hi = gate.supportMax();
  if (gate.type == GateType::Gaussian) {
    // All of N(mu, sigma) that float Box-Muller can reach, negative lengths included.
    lo = gate.mu - 7 * gate.sigma;
    hi = gate.mu + 7 * gate.sigma;
  }
  Chi2Options options;
  options.testCount = kGateCases;
  Chi2Result r = chi2Test1D(samples, samples.size(), lo, hi, 64, [&](double s) { return claimedDensity(gate, s); },
                            options);
  EXPECT_TRUE(r.passed) << r.report;
  EXPECT_NEAR(r.densityMass, 1.0, 1e-6);
}

TEST_P(StatGate, WeightOverPdfAveragesToTheGateIntegral) {
  const Gate& gate = GetParam().gate;
  GateRun run = runGate(gate, 99);
  double sum = 0, sumSq = 0;
  for (const GateOut& o : run.out) {
    // A path length is never negative: the renderer's connection for s < 0 finds nothing.
    double v = o.s >= 0 ? double(o.weightAtS) * double(o.invPdf) : 0.0;
    ASSERT_TRUE(std::isfinite(v)) << "s = " << o.s;
    sum += v;
    sumSq += v * v;
  }
  const double n = double(run.out.size());
  const double mean = sum / n;
  const double standardError = std::sqrt(std::max(0.0, sumSq / n - mean * mean) / (n - 1));
  const double expected = gate.integral();
  // Where W / p is constant (box, bins, gaussians inside the cutoff) the error is zero and only
  // float rounding of each term remains (a few 1e-7 relative).
  EXPECT_NEAR(mean, expected, kMeanZ * standardError + 1e-5 * expected)
      << "standard error " << standardError << ", " << gate.describe();
}

TEST_P(StatGate, GpuWeightMatchesCpu) {
  const Gate& gate = GetParam().gate;
  GateRun run = runGate(gate, 7);
  size_t mismatches = 0, layerMismatches = 0;
  std::string first, firstLayer;
  for (size_t i = 0; i < run.in.size(); ++i) {
    const double length = run.in[i].length;
    const double cpu = gate.weight(length, run.in[i].layer);
    const double gpu = run.out[i].weightAtLength;
    // exp(-z^2/2) in float: z^2/2 <= 21 at the cutoff, relative error about 21 * 2^-22 plus the
    // exp's ulps (Vulkan allows 3 + 2|x|), below 2e-5; zero must be exactly zero.
    if (!(std::abs(gpu - cpu) <= 3e-5 * cpu)) {
      if (mismatches++ == 0)
        first = "L = " + std::to_string(length) + " layer " + std::to_string(run.in[i].layer) +
                ": gpu " + std::to_string(gpu) + ", cpu " + std::to_string(cpu);
    }
    // gateLayers names exactly the layers whose CPU weight can be non-zero at L.
    uint32_t firstLayerCpu = 0, countCpu = 0;
    for (uint32_t k = 0; k < gate.layers(); ++k)
      if (gate.type != GateType::Bins || gate.weight(length, k) > 0) {
        if (countCpu == 0) firstLayerCpu = k;
        ++countCpu;
      }
    const GateOut& o = run.out[i];
    if (o.count != countCpu || (countCpu > 0 && o.first != firstLayerCpu)) {
      if (layerMismatches++ == 0)
        firstLayer = "L = " + std::to_string(length) + ": gpu [" + std::to_string(o.first) + ", +" +
                     std::to_string(o.count) + "), cpu [" + std::to_string(firstLayerCpu) + ", +" +
                     std::to_string(countCpu) + ")";
    }
  }
  EXPECT_EQ(mismatches, 0u) << "first: " << first;
  EXPECT_EQ(layerMismatches, 0u) << "first: " << firstLayer;
}

INSTANTIATE_TEST_SUITE_P(Gates, StatGate, ::testing::ValuesIn(gateCases()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace vktg::test
