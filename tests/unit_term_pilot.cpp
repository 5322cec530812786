// The term pilot's allocation (opt/term_allocation.h) from synthetic pilot runs whose variances and
// times are known: samples ∝ sqrt(variance / seconds per sample) against the interior term, the
// fixed part of a term's time left out of that, the clamps, the path-length boundary's per-pixel
// connections set equal to the interior where they would share its paths (those from the camera
// never), each parameter weighted by its gradient's second moment, and the fallbacks that keep the
// experiment's samples.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "plan/term_allocation.h"

namespace vktg {
namespace {

// Four rounds at termPilotSpp samples; a round's values for parameter k are mean[k] ±
// spread[k] sqrt(spp0 / spp) (the two rounds of each count on either side), so that the variance per
// sample per pixel is 2 spread[k]^2 spp0 whatever the count; seconds = fixed + perSpp × spp.
TermPilotRuns runs(Term term, const std::vector<double>& mean, const std::vector<double>& spread, double fixed,
                   double perSpp, uint32_t spp0 = 16) {
  TermPilotRuns r{term, {}};
  for (uint32_t round = 0; round < 4; ++round) {
    TermPilotRound pilot;
    pilot.spp = termPilotSpp(round, spp0);
    pilot.seconds = fixed + perSpp * pilot.spp;
    const double sign = round < 2 ? 1.0 : -1.0;
    for (size_t k = 0; k < mean.size(); ++k)
      pilot.gradient.push_back(mean[k] + sign * spread[k] * std::sqrt(double(spp0) / pilot.spp));
    r.rounds.push_back(pilot);
  }
  return r;
}

const TermCost& cost(const TermAllocation& a, Term term) {
  for (const TermCost& t : a.terms)
    if (t.term == term) return t;
  throw std::runtime_error(std::string("no term ") + termName(term));
}

TEST(TermPilot, RoundsComeInPairsAtTwoSampleCounts) {
  EXPECT_EQ(termPilotSpp(0, 16), 16u);
  EXPECT_EQ(termPilotSpp(1, 16), 8u);
  EXPECT_EQ(termPilotSpp(2, 16), 16u);
  EXPECT_EQ(termPilotSpp(3, 16), 8u);
  EXPECT_EQ(termPilotSpp(1, 1), 2u);
  EXPECT_EQ(termPilotSpp(1, 3), 1u);
}

TEST(TermPilot, SamplesFollowTheSquareRootOfVarianceOverSecondsPerSample) {
  // One parameter, mean 0: the weight is the summed variance (1 + 1/16 + 4) × 2 spread² at 16 spp.
  const auto a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01), runs(Term::Edge, {0}, {0.25}, 0.0, 0.01),
                                      runs(Term::PathLength, {0}, {2.0}, 0.0, 0.04)},
                                     16);
  EXPECT_NEAR(cost(a, Term::Interior).variance, 1 / 5.0625, 1e-12);
  EXPECT_NEAR(cost(a, Term::PathLength).variance, 4 / 5.0625, 1e-12);
  EXPECT_NEAR(cost(a, Term::Interior).sampleSeconds, 0.16, 1e-12);
  EXPECT_NEAR(cost(a, Term::Interior).fixedSeconds, 0.0, 1e-12);
  // Edges: sqrt(1/16 / 1) = 1/4 of the interior's 16; boundary sqrt(4 / 4) = 1, the same as it.
  EXPECT_EQ(a.sppEdge, 4u);
  EXPECT_EQ(a.sppBoundary, 16u);
  EXPECT_EQ(cost(a, Term::Interior).spp, 16u);
  // Predicted: variance (1 + 4/16 + 4) / (1 + 1/16 + 4), seconds (0.16 + 0.04 + 0.64) / 0.96.
  EXPECT_NEAR(a.varianceRatio, 5.25 / 5.0625, 1e-12);
  EXPECT_NEAR(a.secondsRatio, 0.84 / 0.96, 1e-12);
}

TEST(TermPilot, FixedCostsDoNotCountAgainstSamples) {
  // The edge term costs 10x the interior's time at 16 spp, but almost all of it per render: per
  // sample it is as cheap as the interior, so equal variance gets equal samples.
  auto a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01), runs(Term::Edge, {0}, {1.0}, 1.44, 0.01)}, 16);
  EXPECT_NEAR(cost(a, Term::Edge).fixedSeconds, 1.44, 1e-9);
  EXPECT_EQ(a.sppEdge, 16u);
  // All fixed (a launch-bound term): a tenth of its time counts as per sample, not none.
  a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01), runs(Term::Edge, {0}, {1.0}, 1.6, 0.0)}, 16);
  EXPECT_NEAR(cost(a, Term::Edge).sampleSeconds, 0.16, 1e-9);
  EXPECT_EQ(a.sppEdge, 16u);
}

TEST(TermPilot, ClampsAndTheSharedPathsOfTheBoundaryTerm) {
  // Edges with no variance get the fewest samples; a boundary term 100x as noisy per second is
  // capped at 8x.
  auto a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01), runs(Term::Edge, {0}, {0.0}, 0.0, 0.01),
                                runs(Term::PathLength, {0}, {10.0}, 0.0, 0.01)},
                               16);
  EXPECT_EQ(a.sppEdge, kTermPilotMinSpp);
  EXPECT_EQ(a.sppBoundary, 8u * 16u);
  // Below a sample per pixel the allocation is not rounded up to one: 0.3 of the interior's 10
  // samples (variance 0.09x at the same time) is 3 samples, 0.03 of them 0.3, in sixteenths 0.3125.
  a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01, 10), runs(Term::Edge, {0}, {0.3}, 0.0, 0.01, 10),
                           runs(Term::PathLengthFromCamera, {0}, {0.03}, 0.0, 0.01, 10)},
                          10);
  EXPECT_EQ(a.sppEdge, 3.0);
  EXPECT_EQ(a.sppBoundaryCamera, 0.3125);
  EXPECT_EQ(roundTermSpp(0.97), 1.0);
  EXPECT_EQ(roundTermSpp(2.4), 2.0);
  // A boundary term at 1.3x the interior's samples (variance 1.69x, same time) is set equal to it;
  // at 1.6x it is not.
  a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01, 10), runs(Term::PathLength, {0}, {1.3}, 0.0, 0.01, 10)}, 10);
  EXPECT_EQ(a.sppBoundary, 10u);
  a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01, 10), runs(Term::PathLength, {0}, {1.6}, 0.0, 0.01, 10)}, 10);
  EXPECT_EQ(a.sppBoundary, 16u);
  EXPECT_EQ(a.sppEdge, 0u);  // did not run: the experiment's stays
  EXPECT_EQ(a.sppBoundaryCamera, 0u);
  // The connections from the camera are splatted, never on the interior's paths: 1.3x stays 13.
  a = allocateTermSamples({runs(Term::Interior, {0}, {1.0}, 0.0, 0.01, 10), runs(Term::PathLength, {0}, {0.1}, 0.0, 0.01, 10),
                           runs(Term::PathLengthFromCamera, {0}, {1.3}, 0.0, 0.01, 10)},
                          10);
  EXPECT_EQ(a.sppBoundaryCamera, 13u);
  EXPECT_EQ(a.sppBoundary, 1u);
}

TEST(TermPilot, ParametersCountRelativeToTheirOwnGradient) {
  // Parameter 0's gradient is 1000x parameter 1's; the interior term is noisy on parameter 1 only,
  // the edge term (as noisy in absolute terms) on parameter 0 only, where it is small beside the
  // mean: in units of each parameter's own gradient the interior term's noise dominates.
  const auto a = allocateTermSamples({runs(Term::Interior, {1000.0, 1.0}, {0.0, 1.0}, 0.0, 0.01),
                                      runs(Term::Edge, {0.0, 0.0}, {1.0, 0.0}, 0.0, 0.01)},
                                     16);
  EXPECT_GT(cost(a, Term::Interior).variance, 1e5 * cost(a, Term::Edge).variance);
  EXPECT_EQ(a.sppEdge, kTermPilotMinSpp);
}

TEST(TermPilot, KeepsTheExperimentsSamplesWithoutAnInteriorReference) {
  auto a = allocateTermSamples({runs(Term::Edge, {1.0}, {1.0}, 0.0, 0.01), runs(Term::PathLength, {1.0}, {1.0}, 0.0, 0.01)}, 16);
  EXPECT_EQ(a.sppEdge, 0u);
  EXPECT_EQ(a.sppBoundary, 0u);
  ASSERT_FALSE(a.reasons.empty());
  EXPECT_NE(a.reasons.front().find("does not run"), std::string::npos) << a.reasons.front();
  a = allocateTermSamples({runs(Term::Interior, {1.0}, {0.0}, 0.0, 0.01), runs(Term::Edge, {1.0}, {1.0}, 0.0, 0.01)}, 16);
  EXPECT_EQ(a.sppEdge, 0u);
  EXPECT_NE(a.reasons.front().find("no variance"), std::string::npos) << a.reasons.front();
}

}  // namespace
}  // namespace vktg
