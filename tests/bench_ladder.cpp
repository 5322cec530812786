// The sample count a benchmark curve starts from (firstLadderSpp): raised by powers of two until a
// point takes the time budget, so that a fast device is timed on the estimator and not on launch
// overhead; left alone without a budget or when the base already takes it.
#include <gtest/gtest.h>

#include <vector>

#include "bench/bench_common.h"

namespace vktg {
namespace {

// A device whose runs cost `overhead` seconds plus `perSample` per sample; records the probes.
struct FakeDevice {
  double overhead, perSample;
  std::vector<uint32_t> probes;
  double operator()(uint32_t spp) {
    probes.push_back(spp);
    return overhead + perSample * spp;
  }
};

TEST(BenchLadder, LaunchBoundDeviceGetsEnoughSamplesToReachTheBudget) {
  BenchOptions options;
  options.pointSeconds = 0.05;
  FakeDevice gpu{0.001, 1e-6};  // 1 ms launch, 1 µs a sample: 4 spp would take 1 ms
  const uint32_t spp = firstLadderSpp(4, options, std::ref(gpu));
  EXPECT_GE(gpu.overhead + gpu.perSample * spp, options.pointSeconds);
  // A power of two times the base, and not more than one jump (at most 64x) past the budget.
  EXPECT_EQ(spp % 4, 0u);
  EXPECT_EQ((spp / 4) & (spp / 4 - 1), 0u);
  EXPECT_LT(gpu.overhead + gpu.perSample * (spp / 2), 64 * options.pointSeconds);
  EXPECT_LE(gpu.probes.size(), 6u) << "the count jumps by the time ratio, not one doubling per probe";
}

TEST(BenchLadder, SlowDeviceKeepsTheBaseCount) {
  BenchOptions options;
  options.pointSeconds = 0.05;
  FakeDevice cpu{0.01, 0.02};  // 4 spp take 90 ms
  EXPECT_EQ(firstLadderSpp(4, options, std::ref(cpu)), 4u);
  EXPECT_EQ(cpu.probes.size(), 1u);
}

TEST(BenchLadder, ZeroBudgetTakesTheScaledCountWithoutProbing) {
  BenchOptions options;
  options.pointSeconds = 0;
  options.scale = 0.25;
  FakeDevice gpu{0.001, 1e-6};
  EXPECT_EQ(firstLadderSpp(512, options, std::ref(gpu)), 128u);
  EXPECT_EQ(firstLadderSpp(2, options, std::ref(gpu)), 1u) << "at least one sample";
  EXPECT_TRUE(gpu.probes.empty());
}

TEST(BenchLadder, ADeviceThatReportsNoTimeStopsWhereTheLadderStillFitsARender) {
  BenchOptions options;
  options.pointSeconds = 0.05;
  options.ladderSteps = 5;
  FakeDevice instant{0, 0};
  EXPECT_EQ(firstLadderSpp(1, options, std::ref(instant)), (1u << 30) >> 5) << "the last point has 2^30 spp";
}

}  // namespace
}  // namespace vktg
