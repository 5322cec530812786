// Slow checks of the path-length-boundary term (label slow: each test compiles its own pipeline
// variants): the confocal box gate with standard NEE and with MIS (the total must not depend on the
// NEE mode) and a truncated gaussian gate against quadrature and finite differences. The closed forms are derived in grad_boundary.cpp.
// Comparisons: t-tests with the measured standard errors of both sides, Sidak-corrected (alpha
// 1e-3) over the comparisons of each test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/boundary_test.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

using namespace boundary;

// The same scene rendered with standard NEE and with MIS: the interior term then sees some or all
// of the direct paths through the sensor's sampled ray (ray form), while the boundary pass places
// them with ellipsoidal connections; the total must not depend on that.
TEST(GradSlowBoundary, ConfocalBoxTotalEveryNee) {
  BoxTerms dh = confocalBoxDh(kHeight, kBoxA, kBoxB);
  double dc = confocalBoxDc(kHeight, kBoxA, kBoxB);
  Checker check{sidakLevel(kAlpha, 4)};
  uint32_t seed = 27;
  for (NeeMode nee : {NeeMode::Standard, NeeMode::Mis}) {
    Scene scene = confocalBoxScene(kBoxA, kBoxB, 100000, seed++);
    GradientResult g = gradient(scene, {"t", "c"}, nee);
    std::printf("  %s nee: interior d/dt %.5g, boundary d/dt %.5g (closed-form material split %.5g + %.5g)\n",
                neeModeName(nee), term(g.interior, 0).mean[0], term(g.pathLength, 0).mean[0], -dh.interior, -dh.boundary);
    check.expect(nee == NeeMode::Standard ? "standard nee: d/dt total" : "mis nee: d/dt total", term(g.total, 0),
                 exactLayer({-dh.total}));
    check.expect(nee == NeeMode::Standard ? "standard nee: d/dc total" : "mis nee: d/dc total", term(g.total, 1),
                 exactLayer({dc}));
  }
}

// Truncated gaussian gate (mu 2.8, sigma 0.3, support [2.4, 3.2]): interior and boundary terms are
// both non-zero. References: the quadrature (boundary_test.h) and finite differences.
TEST(GradSlowBoundary, ConfocalTruncatedGaussian) {
  constexpr double kMu = 2.8, kSigma = 0.3;
  const TruncatedGaussianDerivatives exact = truncatedGaussianDerivatives(kMu, kSigma);
  const double dt = exact.dt, dc = exact.dc;
  auto makeScene = [&](uint32_t spp, uint32_t seed) { return truncatedGaussianScene(kMu, kSigma, spp, seed); };
  GradientResult g = gradient(makeScene(100000, 37), {"t", "c"}, NeeMode::Ellipsoidal);
  ASSERT_TRUE(g.plan.pathLength);
  SeedDifference ft = seedFiniteDifference(makeScene(20000, 38), "t", 0.01, kFdSeeds, {});
  SeedDifference fc = seedFiniteDifference(makeScene(20000, 39), "c", 0.01, kFdSeeds, {});
  EXPECT_EQ(ft.nonFinite + fc.nonFinite, 0u);
  Checker check{sidakLevel(kAlpha, 4)};
  check.expect("d/dt total vs quadrature", term(g.total, 0), exactLayer({dt}));
  check.expect("d/dc total vs quadrature", term(g.total, 1), exactLayer({dc}));
  check.expect("d/dt total vs FD", term(g.total, 0), ft.layers[0]);
  check.expect("d/dc total vs FD", term(g.total, 1), fc.layers[0]);
  std::printf("  d/dt: interior %.5g + boundary %.5g; d/dc: interior %.5g + boundary %.5g\n",
              term(g.interior, 0).mean[0], term(g.pathLength, 0).mean[0], term(g.interior, 1).mean[0],
              term(g.pathLength, 1).mean[0]);
}

}  // namespace
}  // namespace vktg::test
