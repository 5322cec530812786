// The interior derivative term (THEORY.md §3, forward mode) against exact derivatives and finite
// differences, on scenes where it is the whole derivative: smooth gates (gaussian), no moving
// silhouette or shadow boundary, no primary or secondary visibility change. The scenes, the
// references and the statistics are described in tests/support/grad_test.h. This file holds the
// checks that fit the default suite: standard NEE at full budget, and MIS NEE and the glossy and
// dielectric planes at reduced budgets (weaker, but every estimator and material runs in CI);
// tests/grad_slow_interior.cpp runs those at full budget, and ellipsoidal NEE (their derivative
// variants are far slower on lavapipe).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/grad_test.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

TEST(GradInterior, StudentQuantiles) {
  // Table values of the two-sided 5% point: 12.706 (1 dof), 2.228 (10), 2.042 (30), 1.960 (normal).
  EXPECT_NEAR(studentTwoSidedQuantile(0.05, 1), 12.7062, 1e-3);
  EXPECT_NEAR(studentTwoSidedQuantile(0.05, 10), 2.2281, 1e-3);
  EXPECT_NEAR(studentTwoSidedQuantile(0.05, 30), 2.0423, 1e-3);
  EXPECT_NEAR(studentTwoSidedQuantile(0.05, 1e9), 1.9600, 1e-3);
  EXPECT_NEAR(studentTwoSidedQuantile(1e-4, 1e5), 3.8906, 2e-3);
  EXPECT_NEAR(studentTwoSidedTail(studentTwoSidedQuantile(1e-6, 15), 15), 1e-6, 1e-9);
}

// The reference itself: the derivative under the integral in r equals the Leibniz form in d.
TEST(GradInterior, ConfocalReferenceLeibniz) {
  ConfocalReference ref = confocalReference();
  const double h = kConfocalHeight, rho = kConfocalRho, intensity = kConfocalIntensity;
  double hi = kConfocalMu + kGaussianCutoff * kConfocalSigma;
  double integral = integrate(
      [](double d) { return std::pow(d, -6) * gaussianWeight(2 * d, kConfocalMu, kConfocalSigma); }, h, 0.5 * hi, 256);
  double m = 2 * rho * intensity * h * h * h * integral;
  double leibniz = 3 * m / h - 2 * rho * intensity * std::pow(h, -3) * gaussianWeight(2 * h, kConfocalMu, kConfocalSigma);
  EXPECT_NEAR(ref.m, m, 1e-9 * m);
  EXPECT_NEAR(ref.dPlane, leibniz, 1e-7 * std::abs(leibniz));
  // The moving lower limit is a large part of the derivative here (the gate covers the shortest path).
  EXPECT_GT(std::abs(leibniz - 3 * m / h), 0.1 * std::abs(leibniz));
  std::printf("  M %.9g, dM/dh %.9g (Leibniz %.9g), dM/dhL %.9g, dM/dmu %.9g\n", ref.m, ref.dPlane, leibniz,
              ref.dLight, ref.dGate);
}

TEST(GradInterior, ConfocalStandardNee) { checkConfocal(NeeMode::Standard, 400000, 11, 16000); }

TEST(GradInterior, PerspectiveDiffusePlane) {
  checkLitPlane(MaterialType::Diffuse, {"albedo", "emission", "plane_z", "light_x"}, 1024, 128);
}

TEST(GradInterior, ConfocalMisNeeReduced) { checkConfocal(NeeMode::Mis, 6000, 14, 16000); }

TEST(GradInterior, PerspectiveGlossyPlaneReduced) { checkLitPlane(MaterialType::Conductor, {"roughness", "plane_z"}, 256, 64); }

TEST(GradInterior, PerspectiveDielectricPlaneReduced) { checkLitPlane(MaterialType::Dielectric, {"ior"}, 256, 64); }

}  // namespace
}  // namespace vktg::test
