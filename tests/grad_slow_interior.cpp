// The interior derivative term, the checks too slow for the default suite (tests/grad_interior.cpp
// has the rest; tests/support/grad_test.h describes scenes, references and statistics): the
// confocal plane with ellipsoidal and MIS next-event estimation (their derivative variants traverse
// the BVH against ellipsoid shells: tens of seconds per 10^5 samples on lavapipe), and the glossy
// (rough conductor) and rough dielectric planes.
#include <gtest/gtest.h>

#include "support/grad_test.h"

namespace vktg::test {
namespace {

TEST(GradInterior, ConfocalEllipsoidalNee) { checkConfocal(NeeMode::Ellipsoidal, 100000, 12, 16000); }

TEST(GradInterior, ConfocalMisNee) { checkConfocal(NeeMode::Mis, 60000, 13, 16000); }

TEST(GradInterior, PerspectiveGlossyPlane) {
  checkLitPlane(MaterialType::Conductor, {"roughness", "albedo", "plane_z"}, 1024, 128);
}

TEST(GradInterior, PerspectiveDielectricPlane) { checkLitPlane(MaterialType::Dielectric, {"ior", "roughness"}, 1024, 128); }

}  // namespace
}  // namespace vktg::test
