// The term pilot's allocation (opt/term_allocation.h) from synthetic pilot runs whose variances and
// times are known: samples ∝ sqrt(variance / seconds) against the interior term, the clamps, the
// path-length boundary set equal to the interior where it would share its paths, each parameter
// weighted by its gradient's second moment, and the fallbacks that keep the experiment's samples.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "opt/term_allocation.h"

namespace vktg {
namespace {

// Four rounds whose values for parameter k are mean[k] ± spread[k] (two of each sign): mean mean[k],
// unbiased variance spread[k]^2 * 4 / 3.
TermPilotRuns runs(const char* term, const std::vector<double>& mean, const std::vector<double>& spread, double seconds) {
  TermPilotRuns r{term, {}, seconds};
  for (int round = 0; round < 4; ++round) {
    std::vector<double> g(mean.size());
    for (size_t k = 0; k < g.size(); ++k) g[k] = mean[k] + ((round % 2) ? spread[k] : -spread[k]);
    r.gradients.push_back(g);
  }
  return r;
}

const TermCost& cost(const TermAllocation& a, const std::string& term) {
  for (const TermCost& t : a.terms)
    if (t.term == term) return t;
  throw std::runtime_error("no term " + term);
}

TEST(TermPilot, SamplesFollowTheSquareRootOfVarianceOverTime) {
  // One parameter, mean 0: the second moment is the summed variance, 4/3 (1 + 1/16 + 4) s².
  const double s = 4.0 / 3.0;
  const auto a = allocateTermSamples({runs("interior", {0}, {1.0}, 0.1), runs("edges", {0}, {0.25}, 0.1),
                                      runs("boundary", {0}, {2.0}, 0.4)},
                                     16);
  const double moment = s * (1 + 0.0625 + 4);
  EXPECT_NEAR(cost(a, "interior").variance, s / moment, 1e-12);
  EXPECT_NEAR(cost(a, "boundary").variance, 4 * s / moment, 1e-12);
  EXPECT_EQ(cost(a, "interior").seconds, 0.1);
  // Edges: sqrt(1/16 / 1) = 1/4 of the interior's 16; boundary sqrt(4 / 4) = 1, the same as it.
  EXPECT_EQ(a.sppEdge, 4u);
  EXPECT_EQ(a.sppBoundary, 16u);
  EXPECT_EQ(cost(a, "interior").spp, 16u);
  // Predicted: variance (1 + 4/16 + 4) / (1 + 1/16 + 4), seconds (0.1 + 0.1/4 + 0.4) / 0.6.
  EXPECT_NEAR(a.varianceRatio, 5.25 / 5.0625, 1e-12);
  EXPECT_NEAR(a.secondsRatio, 0.525 / 0.6, 1e-12);
}

TEST(TermPilot, ClampsAndTheSharedPathsOfTheBoundaryTerm) {
  // Edges with no variance get one sample; a boundary term 100x as noisy per second is capped at 8x.
  auto a = allocateTermSamples({runs("interior", {0}, {1.0}, 1.0), runs("edges", {0}, {0.0}, 1.0),
                                runs("boundary", {0}, {10.0}, 1.0)},
                               16);
  EXPECT_EQ(a.sppEdge, 1u);
  EXPECT_EQ(a.sppBoundary, 8u * 16u);
  // A boundary term at 1.3x the interior's samples (variance 1.69x, same time) is set equal to it;
  // at 1.6x it is not.
  a = allocateTermSamples({runs("interior", {0}, {1.0}, 1.0), runs("boundary", {0}, {1.3}, 1.0)}, 10);
  EXPECT_EQ(a.sppBoundary, 10u);
  a = allocateTermSamples({runs("interior", {0}, {1.0}, 1.0), runs("boundary", {0}, {1.6}, 1.0)}, 10);
  EXPECT_EQ(a.sppBoundary, 16u);
  EXPECT_EQ(a.sppEdge, 0u);  // did not run: the experiment's stays
}

TEST(TermPilot, ParametersCountRelativeToTheirOwnGradient) {
  // Parameter 0's gradient is 1000x parameter 1's; the interior term is noisy on parameter 1 only,
  // the edge term (as noisy in absolute terms) on parameter 0 only, where it is small beside the
  // mean: in units of each parameter's own gradient the interior term's noise dominates.
  const auto a = allocateTermSamples({runs("interior", {1000.0, 1.0}, {0.0, 1.0}, 1.0),
                                      runs("edges", {0.0, 0.0}, {1.0, 0.0}, 1.0)},
                                     64);
  EXPECT_GT(cost(a, "interior").variance, 1e5 * cost(a, "edges").variance);
  EXPECT_EQ(a.sppEdge, 1u);
}

TEST(TermPilot, KeepsTheExperimentsSamplesWithoutAnInteriorReference) {
  auto a = allocateTermSamples({runs("edges", {1.0}, {1.0}, 1.0), runs("boundary", {1.0}, {1.0}, 1.0)}, 16);
  EXPECT_EQ(a.sppEdge, 0u);
  EXPECT_EQ(a.sppBoundary, 0u);
  ASSERT_FALSE(a.reasons.empty());
  EXPECT_NE(a.reasons.front().find("does not run"), std::string::npos) << a.reasons.front();
  a = allocateTermSamples({runs("interior", {1.0}, {0.0}, 1.0), runs("edges", {1.0}, {1.0}, 1.0)}, 16);
  EXPECT_EQ(a.sppEdge, 0u);
  EXPECT_NE(a.reasons.front().find("no variance"), std::string::npos) << a.reasons.front();
}

}  // namespace
}  // namespace vktg
