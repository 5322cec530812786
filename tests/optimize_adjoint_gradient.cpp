// The gradient of a loss by adjoint-weighted accumulation (lossGradient: every term in adjoint
// form, one render per term whatever the number of parameters) against the forward-mode lanes of
// `vktg grad` (renderGradient) contracted with the same adjoint image: sum_q a_q dI_q/dθ_k.
// Both estimate the same derivative with the same samples (same seed, same sampling decisions),
// so they agree sample by sample up to float rounding of their different arithmetic (forward dual
// numbers against reverse-mode adjoints) and the accumulators' fixed point: the tolerance is
// 1e-5 of sum_q |a_q| E|sample_q|, with E|sample| bounded by |mean| + sqrt(spp) std. error. A
// missing or wrong factor moves the result by O(1) of that scale. Scenes cover every parameter
// kind, each term, both cameras, and diffuse, glossy and glass materials; with the interior and
// path-length-boundary terms on one trace of the paths and on a trace each.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "grad/gradient.h"
#include "render/interrupt.h"
#include "support/grad_test.h"
#include "support/render_test.h"
#include "support/room_scene.h"
#include "support/scoped_env.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

// The adjoint image every test here contracts with (support/grad_test.h).
ImageSet adjointImage(uint32_t width, uint32_t height, uint32_t layers) {
  return test::randomAdjointImage(width, height, layers, 11);
}

struct Contracted {
  double value = 0, scale = 0;  // sum a dI/dθ, and sum |a| (|dI/dθ| + sqrt(spp var))
};

Contracted contract(const ImageSet& adjoint, const ImageSet& derivative, const ImageSet& variance, double samples) {
  Contracted c;
  for (size_t l = 0; l < adjoint.layers.size(); ++l)
    for (size_t i = 0; i < adjoint.layers[l].pixels.size(); ++i) {
      double a = adjoint.layers[l].pixels[i], d = derivative.layers[l].pixels[i], v = variance.layers[l].pixels[i];
      c.value += a * d;
      c.scale += std::abs(a) * (std::abs(d) + std::sqrt(samples * std::max(v, 0.0)));
    }
  return c;
}

void expectAdjointMatchesLanes(const Scene& scene, const std::vector<std::string>& names, const GradientOptions& options) {
  const uint32_t width = scene.camera.type == CameraType::PointSensor ? 1 : scene.camera.width;
  const uint32_t height = scene.camera.type == CameraType::PointSensor ? 1 : scene.camera.height;
  const ImageSet adjoint = adjointImage(width, height, scene.gate.layers());

  GradientResult dense = renderGradient(test::testRenderer(), scene, names, options);
  std::vector<uint32_t> indices;
  for (const std::string& n : names) indices.push_back(findParameter(scene, n));
  ParameterModel model(scene, indices);
  std::vector<double> theta(model.size(), 0.0);
  DeviceScene deviceScene(test::testRenderer().context(), model, theta, theta);
  AdjointState state;
  AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  LossGradient sparse = lossGradient(test::testRenderer(), deviceScene, {view}, options, state);
  EXPECT_EQ(sparse.stats.nonFinite, 0u);
  // The stats say how the device traversed the moving scene (its refit 4-wide tree on CPU devices).
  EXPECT_EQ(sparse.stats.wideBvh, deviceScene.gpu().wideBvh());
  EXPECT_EQ(dense.stats.sceneTexels, sparse.stats.sceneTexels);
  // The same plan, but for how the loss gradient groups its passes.
  std::vector<std::string> reasons = sparse.plan.reasons;
  std::erase_if(reasons, [](const std::string& r) { return r.starts_with(kSharedPathsReason); });
  EXPECT_EQ(dense.plan.reasons, reasons);
  // The largest per-pixel sample count among the terms bounds E|sample| from the variance.
  const double samples = std::max({double(scene.render.spp), double(options.sppEdge), double(options.sppBoundary)});
  for (size_t k = 0; k < names.size(); ++k) {
    Contracted c = contract(adjoint, dense.total.derivatives[k], dense.total.variances[k], samples);
    const double tolerance = 1e-5 * c.scale;
    std::printf("%-12s lanes %+.6e  adjoint %+.6e  |difference| %.2e  tolerance %.2e\n", names[k].c_str(), c.value,
                sparse.theta[k], std::abs(sparse.theta[k] - c.value), tolerance);
    EXPECT_NEAR(sparse.theta[k], c.value, tolerance) << names[k];
    // The comparison means something only where the derivative is well above the tolerance.
    EXPECT_GT(std::abs(c.value), 20 * tolerance) << names[k] << ": too small to test";
  }
}

GradientOptions options(uint32_t sppEdge, uint32_t sppBoundary) {
  GradientOptions o;
  o.sppEdge = sppEdge;
  o.sppBoundary = sppBoundary;
  return o;
}

TEST(GradAdjoint, MovingShapeLightAlbedoGateUnderBoxGate) {
  expectAdjointMatchesLanes(test::roomScene(), {"block_x", "bulb_y", "floor_albedo", "t0"}, options(16, 16));
}

TEST(GradAdjoint, BoxGateWithATraceForEachTerm) {
  GradientOptions apart = options(16, 16);
  apart.sharePaths = false;
  expectAdjointMatchesLanes(test::roomScene(), {"block_x", "bulb_y", "floor_albedo", "t0"}, apart);
}

TEST(GradAdjoint, RotationRoughnessEmissionIntensity) {
  Scene scene = test::roomScene();
  scene.gate = parseGateSpec("gaussian:5.8,0.4");
  expectAdjointMatchesLanes(scene, {"spin", "gloss", "lamp_power", "bulb_power"}, options(16, 16));
}

// Free vertex positions (what a vertex_positions entry expands to): x, y and z displacements of
// single vertices, so that vertex accumulators hold all three components. Four parameters, one
// block of forward lanes: a block builds its edge list's CDF from the vertices its own lanes move,
// so lanes in blocks that move other vertices would draw other edge samples than the adjoint.
TEST(GradAdjoint, FreeVertexPositions) {
  Scene scene = test::roomScene();
  std::vector<std::string> names;
  for (auto [vertex, axis] : {std::pair{6u, 0}, {6u, 1}, {6u, 2}, {2u, 1}}) {
    Parameter p;
    p.name = "corner" + std::to_string(vertex) + "xyz"[axis];
    p.kind = ParameterKind::Displace;
    p.target = "block";
    p.axis[axis] = 1.0f;
    p.vertices = {vertex};
    names.push_back(p.name);
    scene.parameters.push_back(std::move(p));
  }
  expectAdjointMatchesLanes(scene, names, options(16, 16));
}

// The model of the named parameters of `scene`.
ParameterModel modelOf(const Scene& scene, const std::vector<std::string>& names) {
  std::vector<uint32_t> indices;
  for (const std::string& n : names) indices.push_back(findParameter(scene, n));
  return ParameterModel(scene, indices);
}

// The room's loss gradient with respect to four of its parameters, against a fixed adjoint image.
struct RoomGradient {
  const std::vector<std::string> names = {"block_x", "bulb_y", "floor_albedo", "t0"};
  const Scene scene = test::roomScene();
  const ParameterModel model = modelOf(scene, names);
  const std::vector<double> theta = std::vector<double>(model.size(), 0.0);
  DeviceScene device{test::testRenderer().context(), model, theta, theta};
  const ImageSet adjoint = adjointImage(scene.camera.width, scene.camera.height, scene.gate.layers());
  const AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  LossGradient operator()(const GradientOptions& o, AdjointState& state) {
    return lossGradient(test::testRenderer(), device, {view}, o, state);
  }
};

// A first scale 2^60 finer than the one a gradient settles on: the largest accumulator would hold
// 2^100, so samples overflow, the passes must report it (each invocation counts its faults once as
// it ends), and the driver must redo the gradient at coarser scales (2^-20 each) until none
// does. It ends 2^20 finer than the settled scale, so it equals the gradient found from the
// settled one up to the accumulators' rounding, far below 1e-6 of the largest entry.
TEST(GradAdjoint, OverflowingAccumulatorsAreRescaled) {
  RoomGradient gradient;
  AdjointState settled;
  gradient(options(8, 8), settled);
  const LossGradient reference = gradient(options(8, 8), settled);
  ASSERT_EQ(reference.attempts, 1u);
  AdjointState fine;
  fine.scale = std::ldexp(settled.scale, 60);
  const LossGradient rescaled = gradient(options(8, 8), fine);
  EXPECT_EQ(rescaled.attempts, 3u);
  EXPECT_EQ(rescaled.stats.gradientOverflows, 0u);
  double largest = 0;
  for (double g : reference.theta) largest = std::max(largest, std::abs(g));
  ASSERT_GT(largest, 0.0);
  for (size_t k = 0; k < gradient.names.size(); ++k)
    EXPECT_NEAR(rescaled.theta[k], reference.theta[k], 1e-6 * largest) << gradient.names[k];
}

// Ctrl-C during a retry (here the second of the three attempts above) must leave the scale the
// gradient started from: an interrupted optimisation checkpoints it, and a resumed run repeats the
// gradient from it, attempt for attempt. The scale of an interrupted attempt would start the resumed
// gradient elsewhere.
TEST(GradAdjoint, GradientInterruptedDuringARetryKeepsItsStartingScale) {
  RoomGradient gradient;
  AdjointState settled;
  gradient(options(8, 8), settled);
  GradientOptions counting = options(8, 8);
  uint32_t batches = 0;
  counting.render.progress = [&](double) { ++batches; };
  AdjointState fine;
  fine.scale = std::ldexp(settled.scale, 60);
  const LossGradient whole = gradient(counting, fine);
  ASSERT_EQ(whole.attempts, 3u);
  ASSERT_EQ(batches % 3, 0u);
  const uint32_t perAttempt = batches / 3;

  GradientOptions interrupting = options(8, 8);
  batches = 0;
  interrupting.render.progress = [&](double) {
    if (++batches == perAttempt + 1) requestInterrupt(2);  // the second attempt's first batch
  };
  AdjointState stopped;
  stopped.scale = std::ldexp(settled.scale, 60);
  EXPECT_THROW(gradient(interrupting, stopped), Interrupted);
  clearInterrupt();
  EXPECT_EQ(batches, perAttempt + 1);
  EXPECT_EQ(stopped.scale, std::ldexp(settled.scale, 60));
  // Resumed from there, the gradient is the uninterrupted one, bit for bit.
  const LossGradient resumed = gradient(options(8, 8), stopped);
  EXPECT_EQ(resumed.attempts, 3u);
  EXPECT_EQ(stopped.scale, fine.scale);
  for (size_t k = 0; k < whole.theta.size(); ++k) EXPECT_EQ(resumed.theta[k], whole.theta[k]) << gradient.names[k];
}

// The accumulators reach the host directly where the device's memory is mapped and cached, through a
// staging copy where it is not (VKTG_DEVICE_MEMORY=staged forces that on any device): the integer
// sums are the same, so the gradient is the same bit for bit.
TEST(GradAdjoint, StagedDeviceMemoryGivesTheSameGradient) {
  const Scene scene = test::roomScene();
  const std::vector<std::string> names = {"block_x", "bulb_y", "floor_albedo", "t0"};
  const ParameterModel model = modelOf(scene, names);
  std::vector<double> theta(model.size(), 0.0);
  const ImageSet adjoint = adjointImage(scene.camera.width, scene.camera.height, scene.gate.layers());
  const AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  AdjointState settled;
  LossGradient mapped;
  {
    Renderer renderer(test::testRenderer().context());
    DeviceScene deviceScene(renderer.context(), model, theta, theta);
    lossGradient(renderer, deviceScene, {view}, options(8, 8), settled);
    AdjointState state;
    state.scale = settled.scale;
    mapped = lossGradient(renderer, deviceScene, {view}, options(8, 8), state);
    ASSERT_EQ(mapped.attempts, 1u);
  }
  test::ScopedEnv env("VKTG_DEVICE_MEMORY", "staged");
  Renderer renderer(test::testRenderer().context());
  DeviceScene deviceScene(renderer.context(), model, theta, theta);
  AdjointState state;
  state.scale = settled.scale;
  const LossGradient staged = lossGradient(renderer, deviceScene, {view}, options(8, 8), state);
  ASSERT_FALSE(state.accumulator->buffer().hostReadable());
  ASSERT_EQ(staged.attempts, 1u);
  for (size_t k = 0; k < names.size(); ++k) EXPECT_EQ(staged.theta[k], mapped.theta[k]) << names[k];
  EXPECT_NE(mapped.theta[0], 0.0);
}

// The loss gradient of `view` with environment variable `variable` set to `first`, then to `second`,
// both at the accumulators' scale a first gradient under `first` settled (so that neither retries):
// for the tests that two ways of running the passes give the same bits.
std::pair<LossGradient, LossGradient> gradientsUnder(const char* variable, const char* first, const char* second,
                                                     const ParameterModel& model, const AdjointView& view,
                                                     const GradientOptions& options) {
  const std::vector<double> theta(model.size(), 0.0);
  auto gradient = [&](const char* value, AdjointState& state) {
    test::ScopedEnv env(variable, value);
    Renderer renderer(test::testRenderer().context());
    DeviceScene deviceScene(renderer.context(), model, theta, theta);
    return lossGradient(renderer, deviceScene, {view}, options, state);
  };
  AdjointState settled;
  gradient(first, settled);
  AdjointState a, b;
  a.scale = b.scale = settled.scale;
  std::pair<LossGradient, LossGradient> both{gradient(first, a), gradient(second, b)};
  EXPECT_EQ(both.first.attempts, 1u);
  EXPECT_EQ(both.second.attempts, 1u);
  return both;
}

// The edge samples sorted by strategy, each strategy's pipeline over its own, or one pipeline for
// all three over every sample (VKTG_EDGE_DISPATCH forces either): every sample takes the same path
// and the accumulators add integers, so the edge term's gradient is the same bit for bit, in one
// batch and in several (each sorts its own samples). The block's silhouette and the bulb's shadow
// of it give each strategy something to find: at 64 edge samples per pixel, leaving out any one
// strategy's dispatch changes the gradient.
TEST(GradAdjoint, EdgeStrategiesApartOrTogetherGiveTheSameGradient) {
  const Scene scene = test::roomScene();
  const std::vector<std::string> names = {"block_x", "bulb_y", "spin"};
  const ParameterModel model = modelOf(scene, names);
  const ImageSet adjoint = adjointImage(scene.camera.width, scene.camera.height, scene.gate.layers());
  const AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  for (uint64_t budget : {uint64_t(0), uint64_t(2) << 20}) {
    SCOPED_TRACE(budget ? "a small memory budget" : "the default memory budget");
    GradientOptions edgesOnly = options(64, 8);
    edgesOnly.interior = edgesOnly.pathLength = false;
    edgesOnly.render.memoryBudget = budget;
    const auto [single, split] = gradientsUnder("VKTG_EDGE_DISPATCH", "single", "split", model, view, edgesOnly);
    if (budget) EXPECT_GT(split.stats.batches, 1u) << "the small budget should split the edge render into batches";
    for (size_t k = 0; k < names.size(); ++k) {
      EXPECT_EQ(split.theta[k], single.theta[k]) << names[k];
      EXPECT_NE(single.theta[k], 0.0) << names[k] << ": the edge term should move it";
    }
  }
}

// A GPU sums the adds of a subgroup's lanes to a shared accumulator before one atomic, a CPU device
// adds each (VKTG_SCATTER forces either): the sums are exact integers modulo 2^64, so every term's
// gradient is the same bit for bit. Every kind of accumulator is hit by many lanes here (the gate's
// and the materials' one slot each, the block's eight vertices), which lavapipe's subgroups of 8
// lanes aggregate; a lost or doubled sum changes the result.
TEST(GradAdjoint, SubgroupSumsOrSingleAddsGiveTheSameGradient) {
  const Scene scene = test::roomScene();
  const std::vector<std::string> names = {"block_x", "spin", "bulb_y", "bulb_power", "floor_albedo", "gloss", "lamp_power", "t0"};
  const ParameterModel model = modelOf(scene, names);
  const ImageSet adjoint = adjointImage(scene.camera.width, scene.camera.height, scene.gate.layers());
  const AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  const auto [direct, aggregated] = gradientsUnder("VKTG_SCATTER", "direct", "aggregate", model, view, options(16, 16));
  for (size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(aggregated.theta[k], direct.theta[k]) << names[k];
    EXPECT_NE(direct.theta[k], 0.0) << names[k];
  }
}

// Point lights follow the emitting triangles in the light table. When a displacement collapses one
// of the lamp's two triangles (vertex 0 onto vertex 1: its area is exactly 0), the table loses an
// entry and the bulb moves up one; an accumulator laid out before must still receive the bulb's
// gradient in the bulb's slots, as a fresh one does.
TEST(GradAdjoint, PointLightSlotsFollowTheLightTableWhenAnEmitterTriangleCollapses) {
  const Scene scene = parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.2, 3], "look_at": [0, 0.2, 0], "fov_y": 40, "resolution": [12, 12]},
    "gate": {"type": "box", "a": 5.2, "b": 6.4},
    "materials": {"floor": {"type": "diffuse", "albedo": 0.6}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "floor", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "lamp", "type": "rectangle", "emission": 4, "transform": {"translate": [0, 1, 0], "scale": 0.25}}
    ],
    "lights": [{"type": "point", "name": "bulb", "position": [-0.8, 1.0, 0.6], "intensity": 1.5}],
    "parameters": [
      {"name": "bulb_y", "type": "light_position", "light": "bulb", "axis": [0, 1, 0]},
      {"name": "pinch", "type": "displace", "shape": "lamp", "vertices": [0], "direction": [1, 0, 0]}
    ],
    "render": {"spp": 16, "max_depth": 3, "seed": 5}
  })", "collapse.json", ".");
  const std::vector<std::string> names = {"bulb_y", "pinch"};
  const ParameterModel model = modelOf(scene, names);
  const std::vector<double> before(model.size(), 0.0), collapsed = {0.0, 0.5};  // (-0.25, 0.75) onto (0.25, 0.75)
  const ImageSet adjoint = adjointImage(scene.camera.width, scene.camera.height, scene.gate.layers());
  const AdjointView view{RenderSetup::of(scene), {}, &adjoint};
  GradientOptions interiorOnly = options(0, 0);
  interiorOnly.edges = interiorOnly.pathLength = false;
  Renderer renderer(test::testRenderer().context());
  DeviceScene deviceScene(renderer.context(), model, before, before);
  AdjointState laidOutBefore;
  lossGradient(renderer, deviceScene, {view}, interiorOnly, laidOutBefore);
  ASSERT_EQ(deviceScene.prepared().lights.size(), 3u);  // the lamp's two triangles, the bulb
  deviceScene.update(collapsed, false);
  ASSERT_EQ(deviceScene.prepared().lights.size(), 2u);
  AdjointState fresh;
  fresh.scale = laidOutBefore.scale;
  const LossGradient reused = lossGradient(renderer, deviceScene, {view}, interiorOnly, laidOutBefore);
  const LossGradient anew = lossGradient(renderer, deviceScene, {view}, interiorOnly, fresh);
  ASSERT_EQ(reused.attempts, 1u);
  ASSERT_EQ(anew.attempts, 1u);
  EXPECT_NE(anew.theta[0], 0.0) << "the bulb's height should change the image";
  EXPECT_EQ(reused.theta[0], anew.theta[0]);
}

// A heightfield (four of its heights) under a near-delta gaussian with ellipsoidal connections and
// antithetic pairs, lit by a point light.
TEST(GradAdjoint, HeightfieldNearDeltaEllipsoidalAntithetic) {
  Scene scene = parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.5, 1.5], "look_at": [0, 0, 0], "fov_y": 45, "resolution": [10, 10]},
    "gate": {"type": "gaussian", "mu": 4.6, "sigma": 0.01},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.7}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [3, 3], "size": [2, 2],
       "heights": [0, 0.1, 0, 0.2, 0.3, 0.1, 0, 0.05, 0], "material": "ground"}
    ],
    "lights": [{"type": "point", "name": "bulb", "position": [0.4, 1.3, 0.8], "intensity": 2}],
    "parameters": [{"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"}],
    "render": {"spp": 32, "max_depth": 3, "seed": 5}
  })", "heights.json", ".");
  expectAdjointMatchesLanes(scene, {"h1", "h3", "h4", "h5"}, options(16, 32));
}

// A point sensor above a glass-covered plane under a box gate: paths start at the sensor (material
// form from the first vertex), the path-length boundary is placed from the sensor's own vertices.
TEST(GradAdjoint, PointSensorGlassAndPlane) {
  Scene scene = parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "point_sensor", "position": [0, 0, 1], "normal": [0, 0, -1]},
    "gate": {"type": "box", "a": 2.1, "b": 2.6},
    "materials": {"wall": {"type": "diffuse", "albedo": 0.8},
                  "glass": {"type": "dielectric", "roughness": 0.3, "ior": 1.4}},
    "shapes": [
      {"name": "plane", "type": "rectangle", "material": "wall", "transform": {"scale": 1.5}},
      {"name": "slab", "type": "cube", "material": "glass",
       "transform": {"translate": [0.3, 0.1, 0.35], "scale": [0.3, 0.3, 0.05]}}
    ],
    "lights": [{"type": "point", "name": "laser", "position": [0, 0, 1], "intensity": 1}],
    "parameters": [
      {"name": "plane_z", "type": "translate", "shape": "plane", "axis": [0, 0, 1]},
      {"name": "slab_x", "type": "translate", "shape": "slab", "axis": [1, 0, 0]},
      {"name": "eta", "type": "ior", "material": "glass"},
      {"name": "t0", "type": "gate_center"}
    ],
    "render": {"spp": 512, "max_depth": 4, "seed": 9}
  })", "sensor.json", ".");
  // The boundary at the scene's spp: its connections share the interior term's paths, from the
  // sensor (generate_camera_rays) on.
  expectAdjointMatchesLanes(scene, {"plane_z", "slab_x", "eta", "t0"}, options(128, 512));
}

}  // namespace
}  // namespace vktg
