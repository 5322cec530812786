// The visibility-boundary term where surfaces nearly or really touch, against central finite
// differences (common random numbers over seeds), on a 0.5 m box beside a diffuse floor, translated
// along x and lit directly (max depth 2, so the interior term has no interreflection between the box
// and the floor, whose singular near field at a contact docs/theory.md 3.3 describes):
//  1. the box 5 cm above the floor under a point light: the shadow of the box's bottom edge falls
//     0.6 mm beside the floor point seen past that edge, the same line in the image as the
//     silhouette. Rays that pass the edge a fixed 8 ray epsilons away jumped the shadow, so the
//     silhouette counted the lit floor and the shadow's boundary counted the same jump again: image
//     sum +9.85 against the finite difference's -0.13 (32 x 32, 4096 samples);
//  2. the box resting on the floor under an area light: its bottom edges lie on the floor, so every
//     boundary segment through them ends on the floor at zero distance;
//  3. a finely faceted grey sphere 5 cm above an emitting floor, which lights it (no other light).
//     Next to the outline the camera sees faces nearly edge-on, narrower in the image than the
//     offset of a ray beside an edge, and rays beside their creases that missed them counted the
//     floor (a black sphere: 29% too much on each side of the outline at 20480 faces); the faces
//     beside its creases and its outline are now taken by name (sample_edges, faceBesideEdge),
//     which the lit faces check, each side's face having its own radiance.
// Image sums and 4 x 4 tiles are compared (a silhouette's pixel coverage has kinks where it crosses
// pixel corners, which a finite difference averages over its step), each a t-test with the measured
// standard errors of both sides, Sidak-corrected (alpha 1e-3) over the comparisons of a test.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/boundary_test.h"
#include "vktg/scene.h"

namespace vktg::test {
namespace {

using namespace boundary;

constexpr uint32_t kResolution = 16, kTile = 4, kFdSeeds = 32, kSppEdge = 2048;
constexpr double kStep = 0.01;

// The box (half size 0.25 m) with its bottom `gap` metres above a 4 m floor, at x = 0.35 so that the
// camera sees its -x side at a grazing angle and the floor beside it; `lighting` is the scene's
// light: a shape (with its comma) or a "lights" entry.
Scene boxNearFloor(double gap, double albedo, const std::string& lighting) {
  const std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 1.6, 2.4], "look_at": [0, 0.2, 0], "fov_y": 40,
               "resolution": [16, 16]},
    "materials": {"floor": {"type": "diffuse", "albedo": 0.7}, "box": {"type": "diffuse", "albedo": )" +
                           std::to_string(albedo) + R"(}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "floor", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "box", "type": "cube", "material": "box",
       "transform": {"translate": [0.35, )" + std::to_string(0.25 + gap) + R"(, 0], "scale": 0.25}})" +
                           lighting + R"(
    "parameters": [{"name": "box_x", "type": "translate", "shape": "box", "axis": [1, 0, 0]}],
    "render": {"spp": 256, "max_depth": 2, "seed": 5}})";
  return parseSceneJson(text, "box_near_floor.json", ".");
}

// The total derivative with respect to `parameter` against finite differences, summed over tiles
// and over the image.
void expectTotalMatchesFd(const Scene& scene, const std::string& parameter = "box_x", uint32_t sppEdge = kSppEdge) {
  GradientOptions options;
  options.sppEdge = sppEdge;
  GradientResult g = renderGradient(testRenderer(), scene, {parameter}, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  EXPECT_TRUE(g.plan.edges);
  SeedDifference fd = seedFiniteDifference(scene, parameter, kStep, kFdSeeds, RenderOptions{});
  EXPECT_EQ(fd.nonFinite, 0u);
  const LayerEstimate total = term(g.total, 0), edge = term(g.edges, 0), reference = fd.layers.at(0);
  std::printf("  gradient %.2f s, finite difference %.2f s; image sums: total %.4f, edge %.4f, fd %.4f\n",
              g.stats.seconds, fd.seconds, sumPixels(total).mean[0], sumPixels(edge).mean[0],
              sumPixels(reference).mean[0]);
  const size_t tiles = (kResolution / kTile) * (kResolution / kTile);
  Checker check{sidakLevel(kAlpha, tiles + 1)};
  check.expect("d/dx total vs fd, tiles", sumTiles(total, kResolution, kTile), sumTiles(reference, kResolution, kTile));
  check.expect("d/dx image sum vs fd", sumPixels(total), sumPixels(reference));
}

TEST(GradContact, ShadowBesideTheSilhouetteOfABoxJustAboveAFloor) {
  // A black box: the silhouette's own jump is from black to the floor's shadow, and all of the
  // derivative is where the shadow of the bottom edge meets the lit floor.
  expectTotalMatchesFd(boxNearFloor(0.05, 0.0, R"(],
    "lights": [{"type": "point", "name": "lamp", "position": [0, 2, 0], "intensity": 3}],)"));
}

TEST(GradContact, BoxRestingOnAFloor) {
  expectTotalMatchesFd(boxNearFloor(0.0, 0.6, R"(,
      {"name": "light", "type": "rectangle", "material": "floor", "emission": 10,
       "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0], "scale": [0.3, 0.3, 1]}}],)"));
}

TEST(GradContact, OutlineOfAFinelyFacetedSphereAgainstAnEmittingFloor) {
  const Scene scene = parseSceneJson(R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 1.6, 2.4], "look_at": [0, 0.2, 0], "fov_y": 40,
               "resolution": [16, 16]},
    "materials": {"black": {"type": "diffuse", "albedo": 0}, "grey": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "black", "emission": 1,
       "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "ball", "type": "sphere", "subdivisions": 5, "material": "grey",
       "transform": {"translate": [0.35, 0.3, 0], "scale": 0.25}}],
    "parameters": [{"name": "ball_x", "type": "translate", "shape": "ball", "axis": [1, 0, 0]}],
    "render": {"spp": 256, "max_depth": 2, "seed": 5}})",
                                     "faceted_sphere.json", ".");
  // More edge samples than the boxes need: a quarter of the old excess on the outline's tiles must
  // stand out of their noise (the gradient takes a second).
  expectTotalMatchesFd(scene, "ball_x", 8 * kSppEdge);
}

}  // namespace
}  // namespace vktg::test
