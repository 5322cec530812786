// A render of several views (Renderer::render with RenderViews, shaders/lib/view.glsl) against each
// view rendered alone. Random numbers are keyed by the view's own pixel, sample and seed, films sum
// a pixel's samples in sample order and loss gradients add into integer accumulators, so every
// view's image, and a loss gradient summed over views, must be bit for bit what the separate renders
// give: a view that read another's camera, light, seed or pixel range would change bits.
#include <gtest/gtest.h>

#include "grad/gradient.h"
#include "support/render_test.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

// A point sensor and a laser (both at the scan point) above a bumpy diffuse surface with a glossy
// block on it, through time bins: a confocal scan's targets. Every view moves the sensor and the
// laser together, as the confocal scan experiment does.
Scene scanScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "point_sensor", "position": [0, 1, 0], "normal": [0, -1, 0]},
    "gate": {"type": "bins", "start": 1.6, "width": 0.1, "count": 8},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.6},
                  "metal": {"type": "conductor", "albedo": 0.8, "roughness": 0.4}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [4, 4], "size": [1.2, 1.2], "material": "ground",
       "heights": [0, 0.05, 0.02, 0, 0.08, 0.15, 0.1, 0.02, 0.03, 0.12, 0.09, 0, 0, 0.02, 0.01, 0]},
      {"name": "block", "type": "cube", "material": "metal", "transform": {"translate": [0.25, 0.2, -0.2], "scale": 0.1}}
    ],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 0], "intensity": 1}],
    "parameters": [
      {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
      {"name": "block_x", "type": "translate", "shape": "block", "axis": [1, 0, 0]},
      {"name": "t0", "type": "gate_center"}
    ],
    "render": {"spp": 256, "max_depth": 4, "seed": 3}
  })", "scan.json", ".");
}

// A pinhole over the same kind of surface, lit by an area lamp and a bulb, under a box gate: the
// interior, edge and path-length-boundary terms (per pixel and from the camera) all have work.
Scene pinholeScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.4, 1.6], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [7, 5]},
    "gate": {"type": "box", "a": 4.2, "b": 5.4},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.6},
                  "metal": {"type": "conductor", "albedo": 0.8, "roughness": 0.35}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [4, 4], "size": [2, 2], "material": "ground",
       "heights": [0, 0.1, 0.05, 0, 0.2, 0.3, 0.1, 0, 0.05, 0.25, 0.15, 0, 0, 0.05, 0.02, 0]},
      {"name": "block", "type": "cube", "material": "metal", "transform": {"translate": [0.2, 0.4, 0], "scale": 0.2}},
      {"name": "lamp", "type": "rectangle", "emission": 6,
       "transform": {"translate": [-0.3, 1.5, 0.2], "rotate": [90, 0, 0], "scale": 0.3}}
    ],
    "lights": [{"type": "point", "name": "bulb", "position": [0.6, 1.1, 0.7], "intensity": 2}],
    "parameters": [
      {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
      {"name": "block_x", "type": "translate", "shape": "block", "axis": [1, 0, 0]},
      {"name": "bulb_y", "type": "light_position", "light": "bulb", "axis": [0, 1, 0]},
      {"name": "albedo", "type": "albedo", "material": "ground"},
      {"name": "t0", "type": "gate_center"}
    ],
    "render": {"spp": 16, "max_depth": 4, "seed": 5}
  })", "pinhole.json", ".");
}

// Three views of `scene`: moved cameras (point sensors: the scan point and the laser with it),
// each with its own seed, two counting optical path outside the scene (a capture's device legs).
std::vector<RenderView> threeViews(const Scene& scene) {
  std::vector<RenderView> views;
  const glm::vec3 moves[] = {{0, 0, 0}, {0.3f, 0.05f, -0.2f}, {-0.25f, -0.1f, 0.3f}};
  const float offsets[] = {0.0f, 0.25f, 0.1f};
  for (uint32_t v = 0; v < 3; ++v) {
    RenderView view{scene.camera, 101 + 7 * v, {}, offsets[v]};
    view.camera.position += moves[v];
    if (scene.camera.type == CameraType::PointSensor) view.lightPositions = {{0u, view.camera.position}};
    else view.lightPositions = {{0u, scene.pointLights[0].position - moves[v]}};
    views.push_back(view);
  }
  return views;
}

// The setup a view is rendered with alone.
RenderSetup setupOf(const Scene& scene, const RenderView& view) {
  RenderSetup setup = RenderSetup::of(scene);
  setup.camera = view.camera;
  setup.settings.seed = view.seed;
  setup.pathOffset = view.pathOffset;
  return setup;
}

void expectViewsRenderAsAlone(const Scene& scene, const RenderOptions& options) {
  Renderer& renderer = test::testRenderer();
  DeviceScene deviceScene(renderer.context(), scene);
  const std::vector<RenderView> views = threeViews(scene);
  const RenderResult together = renderer.render(deviceScene, RenderSetup::of(scene), views, options);
  EXPECT_EQ(together.stats.nonFinite, 0u);
  const std::vector<ImageSet> means = splitViews(together.mean, views.size());
  const std::vector<ImageSet> variances = splitViews(together.variance, views.size());
  double total = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    deviceScene.placePointLights(views[v].lightPositions);
    const RenderResult alone = renderer.render(deviceScene, setupOf(scene, views[v]), options);
    ASSERT_EQ(alone.mean.layers.size(), means[v].layers.size());
    for (size_t l = 0; l < alone.mean.layers.size(); ++l) {
      EXPECT_EQ(alone.mean.layers[l].pixels, means[v].layers[l].pixels) << "view " << v << ", layer " << l;
      EXPECT_EQ(alone.variance.layers[l].pixels, variances[v].layers[l].pixels) << "view " << v << ", layer " << l;
      for (float x : alone.mean.layers[l].pixels) total += x;
    }
  }
  EXPECT_GT(total, 0.0);  // the views saw light: equal zeros would prove nothing
}

TEST(RenderViews, PointSensorsRenderAsAlone) {
  RenderOptions options;
  options.nee = NeeMode::Ellipsoidal;  // connections from the sensor: its position, the laser's
  expectViewsRenderAsAlone(scanScene(), options);
}

TEST(RenderViews, PinholesRenderAsAlone) {
  RenderOptions options;
  options.nee = NeeMode::Mis;  // camera rays, emitter hits, both connection kinds
  expectViewsRenderAsAlone(pinholeScene(), options);
}

// A view's path offset is the gate moved back by it: the same bits as the scene with that gate
// (numbers chosen so that both ways of writing the gate give the same floats).
void expectPathOffsetIsTheGateMovedBack(const Scene& scene, float offset, const RenderOptions& options) {
  Renderer& renderer = test::testRenderer();
  DeviceScene deviceScene(renderer.context(), scene);
  RenderSetup offsetSetup = RenderSetup::of(scene), movedSetup = RenderSetup::of(scene);
  offsetSetup.pathOffset = offset;
  movedSetup.gate = scene.gate.shifted(-double(offset));
  const RenderResult withOffset = renderer.render(deviceScene, offsetSetup, options);
  const RenderResult moved = renderer.render(deviceScene, movedSetup, options);
  const RenderResult plain = renderer.render(deviceScene, RenderSetup::of(scene), options);
  ASSERT_EQ(withOffset.mean.layers.size(), moved.mean.layers.size());
  for (size_t l = 0; l < moved.mean.layers.size(); ++l)
    EXPECT_EQ(withOffset.mean.layers[l].pixels, moved.mean.layers[l].pixels) << "layer " << l;
  double changed = 0;
  for (size_t l = 0; l < plain.mean.layers.size(); ++l)
    for (size_t i = 0; i < plain.mean.layers[l].pixels.size(); ++i)
      changed += std::abs(withOffset.mean.layers[l].pixels[i] - plain.mean.layers[l].pixels[i]);
  EXPECT_GT(changed, 0.0);  // the offset moved light across the gate: equal images would prove nothing
}

TEST(RenderViews, PathOffsetIsTheGateMovedBackAtAPointSensor) {
  Scene scene = scanScene();
  scene.gate = parseGateSpec("bins:1.5,0.125,8");
  for (NeeMode nee : {NeeMode::Standard, NeeMode::Ellipsoidal}) {
    RenderOptions options;
    options.nee = nee;
    expectPathOffsetIsTheGateMovedBack(scene, 0.25f, options);
  }
}

TEST(RenderViews, PathOffsetIsTheGateMovedBackBehindAPinhole) {
  Scene scene = pinholeScene();
  scene.gate = parseGateSpec("box:4.25,5.5");
  RenderOptions options;
  options.nee = NeeMode::Mis;
  expectPathOffsetIsTheGateMovedBack(scene, 0.5f, options);
}

// A loss gradient over three views, each with its own adjoint image: one render per term for all of
// them against one per term and view.
void expectGradientOfViewsAsOneByOne(const Scene& scene, GradientOptions options) {
  Renderer& renderer = test::testRenderer();
  std::vector<uint32_t> all(scene.parameters.size());
  for (uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  const ParameterModel model(scene, all);
  std::vector<double> theta(model.size(), 0.0);
  DeviceScene deviceScene(renderer.context(), model, theta, theta);
  const std::vector<RenderView> renderViews = threeViews(scene);
  std::vector<ImageSet> adjoints;
  for (size_t v = 0; v < renderViews.size(); ++v) {
    const glm::uvec2 size = imagePixels(scene.camera);
    ImageSet a{size.x, size.y, {}};
    for (uint32_t l = 0; l < scene.gate.layers(); ++l) {
      ImageLayer layer;
      for (uint32_t i = 0; i < size.x * size.y; ++i) layer.pixels.push_back(float((i * 7 + l * 3 + v * 5) % 11) / 5.0f - 1.0f);
      a.layers.push_back(layer);
    }
    adjoints.push_back(a);
  }
  std::vector<AdjointView> views;
  for (size_t v = 0; v < renderViews.size(); ++v)
    views.push_back({setupOf(scene, renderViews[v]), renderViews[v].lightPositions, &adjoints[v]});

  AdjointState batchedState, separateState;
  options.batchViews = true;
  const LossGradient batched = lossGradient(renderer, deviceScene, views, options, batchedState);
  options.batchViews = false;
  const LossGradient separate = lossGradient(renderer, deviceScene, views, options, separateState);
  EXPECT_EQ(batched.stats.nonFinite, 0u);
  EXPECT_EQ(batched.stats.paths, separate.stats.paths);
  EXPECT_EQ(batched.attempts, separate.attempts);
  // One render per term: a third of the batches (every render here fits one batch).
  EXPECT_EQ(3 * batched.stats.batches, separate.stats.batches);
  ASSERT_EQ(batched.theta.size(), separate.theta.size());
  double norm = 0;
  for (size_t k = 0; k < batched.theta.size(); ++k) {
    EXPECT_EQ(batched.theta[k], separate.theta[k]) << scene.parameters[k].name;
    norm += std::abs(batched.theta[k]);
  }
  EXPECT_GT(norm, 0.0);
}

TEST(RenderViews, PointSensorLossGradientAsOneByOne) {
  GradientOptions options;
  options.sppEdge = 64;
  expectGradientOfViewsAsOneByOne(scanScene(), options);
}

TEST(RenderViews, PinholeLossGradientAsOneByOne) {
  GradientOptions options;  // interior and per-pixel boundary on one trace, edges, boundary from the camera
  options.sppEdge = 16;
  expectGradientOfViewsAsOneByOne(pinholeScene(), options);
}

// Only views that one render can hold go together: the same gate, settings but the seed, camera
// type and image size, up to 2^20 pixels. Groups keep the views' order.
TEST(RenderViews, GroupsHoldOnlyViewsThatRenderTogether) {
  const Scene scene = pinholeScene();
  auto view = [&](auto change) {
    AdjointView v{RenderSetup::of(scene), {}, nullptr};
    change(v.setup);
    return v;
  };
  const std::vector<AdjointView> views = {
      view([](RenderSetup&) {}),
      view([](RenderSetup& s) { s.settings.seed = 99; s.camera.position.x += 1; }),  // with the first
      view([](RenderSetup& s) { s.gate.b += 0.1; }),
      view([](RenderSetup& s) { s.settings.spp *= 2; }),
      view([](RenderSetup& s) { s.camera.width += 1; }),
      view([](RenderSetup& s) { s.camera.type = CameraType::PointSensor; }),
      view([](RenderSetup& s) { s.camera.lookAt.y += 0.2f; }),  // with the first
  };
  const std::vector<std::vector<size_t>> expected = {{0, 1, 6}, {2}, {3}, {4}, {5}};
  EXPECT_EQ(viewGroups(views, true), expected);
  EXPECT_EQ(viewGroups(views, false).size(), views.size());
  // A group holds at most 2^20 pixels: 1024 x 512 images go two by two.
  std::vector<AdjointView> large(5, view([](RenderSetup& s) { s.camera.width = 1024, s.camera.height = 512; }));
  const std::vector<std::vector<size_t>> pairs = {{0, 1}, {2, 3}, {4}};
  EXPECT_EQ(viewGroups(large, true), pairs);
}

}  // namespace
}  // namespace vktg
