// The visibility-boundary (edge) term (THEORY.md §3, shaders/lib/edge.glsl) against central finite
// differences (common random numbers, spread over seeds), per pixel, on scenes where moving
// geometry changes what is visible:
//  1. a primary silhouette: a black square in front of an emissive wall, seen by a pinhole and
//     translated sideways. Nothing else changes, so the derivative is the edge term alone: the
//     wall's radiance uncovered on one side of the square and covered on the other;
//  2. a moving occluder's shadow (scenes/occluder_shadow.json): a square between a ceiling light
//     and a floor, translated sideways under a wide gaussian gate (no jumps): interior + edge, and
//     the edge term carries almost all of it (the interior term alone is rejected);
//  3. all three terms together: the same scene under a box gate, whose jumps add the path-length
//     boundary of the paths that bounce off the moving square;
//  4. a moving point light: the same square and floor lit by a point light that moves sideways,
//     so the shadow moves with the light's velocity at the light end of the boundary segment;
//  5. a shadow seen only via a bounce: the camera sees a wall lit by the floor, never the floor,
//     the occluder or a shadow on the wall, so every boundary segment is the path's second or third
//     (the camera-side walk of sample_edges at depth 2);
//  6. a shadow seen only through glass: the camera looks at the floor through a rough glass slab,
//     so the walk refracts on its way back, and under a gaussian gate the slab's optical length
//     counts;
//  7. a shadow cast inside glass: the square floats inside a glass block over an emissive floor,
//     and the camera sees only the ceiling, so every boundary segment runs inside the glass and
//     the walk leaves it by one refraction, whose weight needs the non-reciprocal factor
//     (eta_wo / eta_toward)^2 (measured without it: 2.2x the finite difference).
//  8. creases behind a pinhole: the default room's short box, lifted off the floor and moved, seen
//     with its lit top beside its unlit sides; the jump between them moves across the image with
//     the creases, which the primary strategy samples like silhouettes.
// Every comparison is a t-test with the measured standard errors of both sides, Sidak-corrected
// (alpha 1e-3) over all pixels and comparisons of its test.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "support/boundary_test.h"
#include "vktg/scene.h"

namespace vktg::test {
namespace {

using namespace boundary;

constexpr uint32_t kResolution = 16, kFdSeedsEdge = 32;

GradientResult edgeGradient(const Scene& scene, const std::string& parameter, uint32_t sppEdge) {
  GradientOptions options;
  options.sppEdge = sppEdge;
  GradientResult g = renderGradient(testRenderer(), scene, {parameter}, options);
  EXPECT_EQ(g.stats.nonFinite, 0u);
  EXPECT_TRUE(g.plan.edges);
  std::printf("  gradient: %.2f s; %llu silhouette-capable edges, %llu of %llu edge samples silhouettes, %llu reached the camera\n",
              g.stats.seconds, (unsigned long long)g.stats.silhouetteEdges, (unsigned long long)g.stats.edgeSilhouettes,
              (unsigned long long)(uint64_t(sppEdge) * kResolution * kResolution),
              (unsigned long long)g.stats.edgeConnected);
  return g;
}

LayerEstimate finiteDifference(const Scene& scene, const std::string& parameter, double eps) {
  SeedDifference fd = seedFiniteDifference(scene, parameter, eps, kFdSeedsEdge, RenderOptions{});
  EXPECT_EQ(fd.nonFinite, 0u);
  std::printf("  finite difference (eps %g, %u seeds): %.2f s\n", eps, kFdSeedsEdge, fd.seconds);
  return fd.layers.at(0);
}

// How many pixels the interior term alone gets wrong: the edge term must matter in these scenes.
size_t rejectedWithoutEdges(const GradientResult& g, const LayerEstimate& fd, double level) {
  LayerEstimate interior = term(g.interior, 0);
  if (!g.pathLength.derivatives.empty()) interior = sumLayers({interior, term(g.pathLength, 0)});
  PixelCheck c = checkPixels(interior, fd, level);
  std::printf("  without the edge term: %zu of %zu pixels rejected, worst %s\n", c.rejected, c.tested, c.worst.c_str());
  return c.rejected;
}

// The total derivative against finite differences of step `eps` (every pixel), and the edge
// term's weight: at least `minRejected` pixels must fail without it.
void expectMatchesFd(const Scene& scene, const GradientResult& g, const std::string& parameter, double eps,
                     size_t minRejected) {
  LayerEstimate fd = finiteDifference(scene, parameter, eps);
  double level = sidakLevel(kAlpha, kResolution * kResolution);
  Checker{level}.expect(("d/d" + parameter + " total vs fd").c_str(), term(g.total, 0), fd);
  EXPECT_GT(rejectedWithoutEdges(g, fd, level), minRejected);
}

// Appends parameter `name` of `kind`, acting on `target` along `axis`.
void addParameter(Scene& scene, const std::string& name, ParameterKind kind, const std::string& target, glm::vec3 axis) {
  Parameter p;
  p.name = name;
  p.kind = kind;
  p.target = target;
  p.axis = axis;
  scene.parameters.push_back(std::move(p));
}

// The derivative of the shadow jumps where the penumbra meets the umbra or the lit floor (a straight
// edge uncovers a rectangular light linearly), and a silhouette's pixel coverage has kinks where it
// crosses pixel corners: a finite difference averages the derivative over ±eps there. This step
// moves the shadow by 0.02 pixel at 16x16 (0.2 pixel at 0.02 failed exactly at those pixels).
constexpr double kOccluderStep = 0.002;

Scene occluderScene(uint32_t spp) {
  Scene scene = loadScene(std::string(VKTG_SOURCE_DIR) + "/scenes/occluder_shadow.json");
  scene.camera.width = scene.camera.height = kResolution;
  scene.render.spp = spp;
  scene.render.seed = 5;
  return scene;
}

// The parameter square_x of `sceneText` moves a black square sideways: its own paths end on it, so
// the interior term is exactly 0 and the derivative is the edge term alone. Checks the total against
// finite differences of step `eps` summed over tiles of tile x tile pixels (1: every pixel) and over
// the image, the interior term against 0, and that more than 10 pixels fail without the edge term.
void expectBlackSquareEdgeTerm(const std::string& sceneText, uint32_t sppEdge, double eps, size_t tile = 1) {
  Scene scene = parseSceneJson(sceneText, "black_square.json", ".");
  GradientResult g = edgeGradient(scene, "square_x", sppEdge);
  LayerEstimate fd = finiteDifference(scene, "square_x", eps);
  const size_t tiles = (kResolution / tile) * (kResolution / tile);
  double level = sidakLevel(kAlpha, tiles + 1 + kResolution * kResolution);
  Checker check{level};
  check.expect(tile == 1 ? "d/dx total vs fd" : "d/dx total vs fd, tiles", sumTiles(term(g.total, 0), kResolution, tile),
               sumTiles(fd, kResolution, tile));
  check.expect("d/dx image sum vs fd", sumPixels(term(g.total, 0)), sumPixels(fd));
  check.expect("d/dx interior = 0", term(g.interior, 0), exactLayer(std::vector<double>(fd.mean.size(), 0.0)));
  EXPECT_GT(rejectedWithoutEdges(g, fd, level), 10u);
}

TEST(GradEdge, PrimarySilhouetteOfABlackSquare) {
  std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 30, "resolution": [16, 16]},
    "gate": {"type": "steady"},
    "materials": {"black": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"name": "wall", "type": "rectangle", "material": "black", "emission": 1, "transform": {"translate": [0, 0, -1], "scale": 3}},
      {"name": "square", "type": "rectangle", "material": "black", "transform": {"translate": [0.1, 0.05, 0], "scale": 0.35}}],
    "parameters": [{"name": "square_x", "type": "translate", "shape": "square", "axis": [1, 0, 0]}],
    "render": {"spp": 64, "max_depth": 2, "seed": 3}})";
  Scene scene = parseSceneJson(text, "primary.json", ".");
  GradientResult g = edgeGradient(scene, "square_x", 1024);
  LayerEstimate fd = finiteDifference(scene, "square_x", 0.01);
  double level = sidakLevel(kAlpha, 2 * kResolution * kResolution);
  Checker{level}.expect("d/dx total (interior + edge) vs fd", term(g.total, 0), fd);
  // The wall's radiance is constant and the square is black: the interior term is exactly 0.
  Checker{level}.expect("d/dx interior = 0", term(g.interior, 0), exactLayer(std::vector<double>(fd.mean.size(), 0.0)));
  EXPECT_GT(rejectedWithoutEdges(g, fd, level), 10u);
}

TEST(GradEdge, MovingOccluderShadow) {
  Scene scene = occluderScene(256);
  GradientResult g = edgeGradient(scene, "occluder_x", 2048);
  EXPECT_FALSE(g.plan.pathLength) << "a gaussian gate has no jumps";
  expectMatchesFd(scene, g, "occluder_x", kOccluderStep, 10);
}

TEST(GradEdge, AllThreeTermsUnderABoxGate) {
  Scene scene = occluderScene(256);
  scene.gate = Gate{};
  scene.gate.type = GateType::Box;
  scene.gate.a = 5.8;
  scene.gate.b = 6.8;
  GradientResult g = edgeGradient(scene, "occluder_x", 2048);
  EXPECT_TRUE(g.plan.pathLength && g.plan.interior);
  expectMatchesFd(scene, g, "occluder_x", kOccluderStep, 10);
}

TEST(GradEdge, MovingPointLightShadow) {
  Scene scene = occluderScene(256);
  scene.shapes.pop_back();  // the area light
  scene.pointLights.push_back({"lamp", {0.0f, 2.0f, 0.0f}, 4.0f});
  addParameter(scene, "lamp_x", ParameterKind::LightPosition, "lamp", {1.0f, 0.0f, 0.0f});
  GradientResult g = edgeGradient(scene, "lamp_x", 2048);
  // The lamp's shadow rim covers fewer pixels (measured: 11 of 256 rejected without the edge
  // term, worst t 15).
  expectMatchesFd(scene, g, "lamp_x", kOccluderStep, 5);
}

TEST(GradEdge, ShadowSeenOnlyViaABounce) {
  // The black square hangs between a ceiling light and the floor; the pinhole looks level at a
  // wall 4 m away with a 20 degree field of view, below the light and above the square and the
  // floor, and lines from the wall to the light pass above the square. Black square: its own
  // paths end there, so the interior term is exactly 0 and the derivative is the edge term of
  // boundary segments that start on the wall (segment 2: wall -> floor past the square) or on the
  // floor (segment 3: floor -> light). The wall's light from the floor is an integral over the
  // shadow, smooth in the square's position, so a large FD step is exact enough.
  std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [1.9, 1.5, 0], "look_at": [-2, 1.5, 0], "fov_y": 20, "resolution": [16, 16]},
    "gate": {"type": "steady"},
    "materials": {"white": {"type": "diffuse", "albedo": 0.8}, "black": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "white", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "wall", "type": "rectangle", "material": "white", "transform": {"translate": [-2, 1.5, 0], "rotate": [0, 90, 0], "scale": 1.5}},
      {"name": "square", "type": "rectangle", "material": "black", "transform": {"translate": [0.2, 1, 0], "rotate": [90, 0, 0], "scale": [0.3, 0.3, 1]}},
      {"name": "light", "type": "rectangle", "material": "black", "emission": 20, "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0], "scale": [0.2, 0.2, 1]}}],
    "parameters": [{"name": "square_x", "type": "translate", "shape": "square", "axis": [1, 0, 0]}],
    "render": {"spp": 256, "max_depth": 3, "seed": 3}})";
  expectBlackSquareEdgeTerm(text, 8192, 0.05);
}

TEST(GradEdge, ShadowSeenOnlyThroughGlass) {
  // The black square hangs between a small ceiling light and the floor; a slab of rough glass
  // 0.5 m thick, above the light, fills the pinhole's view of the floor. Every boundary segment
  // (light -> floor past the square) reaches the camera through the slab: the walk goes floor ->
  // slab underside, refracts in by a BSDF sample, and connects from the slab's top through the
  // second refraction. Black square: the interior term is exactly 0. The gaussian gate (centre
  // 5.4 m, sigma 0.25 m) weighs the slab's optical length, 0.75 m of the paths' 5-5.5 m against
  // 0.5 m geometric: measured with the walk counting geometric length, image sum -4.7 +- 0.9
  // against the finite difference's 7.1 +- 0.8.
  std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 3.5, 1], "look_at": [0, 0, 0], "fov_y": 30, "resolution": [16, 16]},
    "gate": {"type": "gaussian", "mu": 5.4, "sigma": 0.25},
    "materials": {"white": {"type": "diffuse", "albedo": 0.8}, "black": {"type": "diffuse", "albedo": 0},
                  "glass": {"type": "dielectric", "roughness": 0.1, "ior": 1.5}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "white", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "slab", "type": "cube", "material": "glass", "transform": {"translate": [0, 1.75, 0], "scale": [3, 0.25, 3]}},
      {"name": "square", "type": "rectangle", "material": "black", "transform": {"translate": [0.2, 0.6, 0], "rotate": [90, 0, 0], "scale": [0.25, 0.25, 1]}},
      {"name": "light", "type": "rectangle", "material": "black", "emission": 20, "transform": {"translate": [0, 1.2, 0], "rotate": [90, 0, 0], "scale": [0.15, 0.15, 1]}}],
    "parameters": [{"name": "square_x", "type": "translate", "shape": "square", "axis": [1, 0, 0]}],
    "render": {"spp": 1024, "max_depth": 5, "seed": 3}})";
  expectBlackSquareEdgeTerm(text, 16384, 0.01);
}

TEST(GradEdge, ShadowCastInsideGlass) {
  // A block of rough glass holds the black square; the floor below emits, the ceiling above
  // reflects, and the pinhole, between them beside the block, looks up at the ceiling only. The
  // square's shadow on the ceiling is seen via the ceiling: its boundary segments (sample_edges'
  // uniform directions at the square's edges) end on the block's faces from inside, and the walk
  // refracts out of the top face to the ceiling, then connects. The interior term is exactly 0
  // (black square); the ceiling's light is an integral over a shadow blurred by the glass, smooth
  // in the square's position, so a large step is exact enough. Few walks come back this way (about
  // 1 edge sample in 400), too few for every pixel to see one: tiles of 4 x 4 pixels are compared.
  // Measured without the refraction factor (at half these edge samples): image sum -25.2 +- 2.4
  // against the finite difference's -11.2 +- 0.2.
  std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [1.9, 1.7, 0], "look_at": [-2, 2.9, 0], "fov_y": 20, "resolution": [16, 16]},
    "gate": {"type": "steady"},
    "materials": {"white": {"type": "diffuse", "albedo": 0.8}, "black": {"type": "diffuse", "albedo": 0},
                  "glass": {"type": "dielectric", "roughness": 0.3, "ior": 1.5}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "black", "emission": 2, "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "ceiling", "type": "rectangle", "material": "white", "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0], "scale": 2}},
      {"name": "block", "type": "cube", "material": "glass", "transform": {"translate": [0, 0.8, 0], "scale": [0.6, 0.3, 0.6]}},
      {"name": "square", "type": "rectangle", "material": "black", "transform": {"translate": [0.1, 0.8, 0], "rotate": [90, 0, 0], "scale": [0.25, 0.25, 1]}}],
    "parameters": [{"name": "square_x", "type": "translate", "shape": "square", "axis": [1, 0, 0]}],
    "render": {"spp": 1024, "max_depth": 4, "seed": 3}})";
  expectBlackSquareEdgeTerm(text, 65536, 0.02, 4);
}

TEST(GradEdge, CreasesOfALitBoxBehindAPinhole) {
  // The default room at max depth 2 (direct light only): the short box's top face is lit, its two
  // visible sides face away from the ceiling light and are black, so every crease between the top
  // and a side carries the top's whole radiance as a jump. Lifted 2 cm, the box does not touch the
  // floor. Moving it up moves those creases across the image. Measured before creases were sampled
  // (32 x 32, 1024 spp): image sum +15.7 to +16.1 against the finite difference's -23.4 to -24.5;
  // with a black box, where no crease carries a jump, the two agreed. A silhouette's pixel coverage
  // has kinks where it crosses pixel corners, which a finite difference averages over its step, so
  // tiles of 4 x 4 pixels and the image sum are compared.
  Scene scene = loadScene(std::string(VKTG_SOURCE_DIR) + "/scenes/cornell_box.json");
  scene.camera.width = scene.camera.height = kResolution;
  scene.render.spp = 256;
  scene.render.maxDepth = 2;
  scene.render.seed = 5;
  scene.gate = Gate{};
  for (Shape& shape : scene.shapes)
    if (shape.name == "short_box")
      for (glm::vec3& p : shape.positions) p.y += 0.02f;
  addParameter(scene, "box_y", ParameterKind::Translate, "short_box", {0.0f, 1.0f, 0.0f});
  GradientResult g = edgeGradient(scene, "box_y", 1024);
  LayerEstimate fd = finiteDifference(scene, "box_y", 0.01);
  constexpr uint32_t kTile = 4;
  const size_t tiles = (kResolution / kTile) * (kResolution / kTile);
  Checker check{sidakLevel(kAlpha, tiles + 1)};
  check.expect("d/dy total vs fd, tiles", sumTiles(term(g.total, 0), kResolution, kTile), sumTiles(fd, kResolution, kTile));
  check.expect("d/dy image sum vs fd", sumPixels(term(g.total, 0)), sumPixels(fd));
}

}  // namespace
}  // namespace vktg::test
