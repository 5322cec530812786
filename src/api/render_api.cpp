// vktg::render, vktg::derivatives and vktg::renderBackward: the command line's renders as
// functions. Each does what `vktg render`, `vktg grad` and the gradient of `vktg optimize` do with
// the same settings, so that their images are the command line's bit for bit.
#include <cmath>

#include "api/context_impl.h"
#include "grad/gradient.h"
#include "render/nee_pilot.h"
#include "render/planner.h"
#include "render/renderer.h"
#include "render/scan_views.h"
#include "scene/scan.h"
#include "vktg/parameter_model.h"
#include "vktg/vktg.h"

namespace vktg {
namespace {

// The model's scene at its current values with the request's settings, checked as the command
// line checks its options (the same limits, the field named by its option's name).
Scene requestedScene(const Model& model, const RenderRequest& r) {
  Scene scene = model.current();
  if (r.gate) {
    validateGate(*r.gate, "", "gate");
    scene.gate = *r.gate;
  }
  if (r.spp) {
    if (*r.spp < 1 || *r.spp > (1u << 24)) fail("", "spp", std::to_string(*r.spp) + " is not within 1..16777216");
    scene.render.spp = *r.spp;
  }
  if (r.seed) scene.render.seed = *r.seed;
  if (r.maxDepth) {
    if (*r.maxDepth < 1 || *r.maxDepth > 1024) fail("", "max_depth", std::to_string(*r.maxDepth) + " is not within 1..1024");
    scene.render.maxDepth = *r.maxDepth;
  }
  if (r.resolution) {
    const auto [w, h] = *r.resolution;
    if (w == 0 || h == 0 || w > 16384 || h > 16384)
      fail("", "resolution", std::to_string(w) + "x" + std::to_string(h) + " must have 1 <= width, height <= 16384");
    if (scene.camera.type == CameraType::PointSensor) fail("", "resolution", "the scene's camera is a point sensor (one pixel)");
    scene.camera.width = w;
    scene.camera.height = h;
  }
  return scene;
}

std::vector<RenderView> renderViews(const Scene& scene, const std::vector<View>& views) {
  std::vector<RenderView> out;
  for (size_t k = 0; k < views.size(); ++k) {
    const View& v = views[k];
    if (v.camera.type != scene.camera.type || imagePixels(v.camera) != imagePixels(scene.camera))
      fail("", "views[" + std::to_string(k) + "].camera", "its type and image size must be the scene's");
    for (const auto& [light, position] : v.lightPositions) {
      if (light >= scene.pointLights.size())
        fail("", "views[" + std::to_string(k) + "].lights",
             "point light " + std::to_string(light) + " is not in the scene (it has " +
                 std::to_string(scene.pointLights.size()) + ")");
      if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
        fail("", "views[" + std::to_string(k) + "].lights", "a position is not finite");
    }
    out.push_back({v.camera, v.seed, v.lightPositions, v.pathOffset});
  }
  return out;
}

GradientOptions gradientOptions(Context& context, const GradRequest& r, bool forward) {
  GradientOptions g;
  g.interior = r.interior;
  g.edges = r.edge;
  g.pathLength = r.pathLength;
  for (auto [spp, field] : {std::pair{r.sppEdge, "spp_edge"}, std::pair{r.sppBoundary, "spp_boundary"},
                            std::pair{r.sppBoundaryCamera, "spp_boundary_camera"}}) {
    if (!(spp >= 0) || spp > (1u << 24)) fail("", field, "must be 0 (spp) or a positive count up to 16777216");
    // Forward lanes run per-pixel passes at whole samples per pixel.
    if (forward && spp != std::floor(spp)) fail("", field, "derivative images take whole samples per pixel");
  }
  g.sppEdge = r.sppEdge;
  g.sppBoundary = r.sppBoundary;
  g.sppBoundaryCamera = r.sppBoundaryCamera;
  g.antithetic = !r.antithetic ? AntitheticMode::Auto : *r.antithetic ? AntitheticMode::On : AntitheticMode::Off;
  g.render.nee = r.nee;
  g.render.memoryBudget = context.memoryBudget();
  g.render.progress = r.progress;
  return g;
}

std::vector<ImageSet> viewImages(const ImageSet& stacked, size_t views) {
  return views == 0 ? std::vector<ImageSet>{stacked} : splitViews(stacked, views);
}

}  // namespace

std::vector<View> scanViews(const Model& model, const std::filesystem::path& scanFile) {
  const Scene scene = model.current();
  std::vector<View> out;
  for (const RenderView& v : scanViews(loadScan(scanFile, scene), scene)) out.push_back({v.camera, v.seed, v.lightPositions, v.pathOffset});
  return out;
}

Rendered render(Context& context, const Model& model, const RenderRequest& request) {
  const Scene scene = requestedScene(model, request);
  const std::vector<RenderView> views = renderViews(scene, request.views);
  Renderer& renderer = context.impl().renderer;
  DeviceScene deviceScene(context.impl().vulkan, scene);
  RenderSetup setup = RenderSetup::of(scene);
  RenderOptions options;
  options.nee = request.nee;
  options.memoryBudget = context.memoryBudget();
  if (!views.empty()) {
    // The pilot measures the first view (as `vktg render --scan`).
    setup.camera = views.front().camera;
    deviceScene.placePointLights(views.front().lightPositions);
  }
  if (request.pilot) chooseNeeByPilot(renderer, deviceScene, setup, options, true);
  options.progress = request.progress;
  const RenderResult r =
      views.empty() ? renderer.render(deviceScene, setup, options) : renderer.render(deviceScene, setup, views, options);
  Rendered out;
  out.images = viewImages(r.mean, views.size());
  out.variances = viewImages(r.variance, views.size());
  out.plan = explainPlan(r.plan);
  out.nonFinite = r.stats.nonFinite;
  out.seconds = r.stats.seconds;
  return out;
}

Derivatives derivatives(Context& context, const Model& model, const std::vector<std::string>& parameters,
                        const GradRequest& request) {
  const Scene scene = requestedScene(model, request);
  const std::vector<RenderView> views = renderViews(scene, request.views);
  for (const std::string& name : parameters) findParameter(scene, name, "parameters");
  const GradientResult r = renderGradient(context.impl().renderer, scene, parameters, gradientOptions(context, request, true), views);
  Derivatives out;
  out.parameters = r.parameters;
  out.image = r.primal.mean;
  out.total = r.total.derivatives;
  out.totalVariance = r.total.variances;
  out.interior = r.interior.derivatives;
  out.edge = r.edges.derivatives;
  out.pathLength = r.pathLength.derivatives;
  out.plan = r.plan.reasons;
  return out;
}

std::vector<double> renderBackward(Context& context, const Model& model, const std::vector<std::string>& parameters,
                                   const std::vector<ImageSet>& adjoints, const GradRequest& request) {
  if (parameters.empty()) fail("", "parameters", "no parameters selected");
  const Scene scene = requestedScene(model, request);
  const std::vector<RenderView> views = renderViews(scene, request.views);
  const size_t expected = views.empty() ? 1 : views.size();
  if (adjoints.size() != expected)
    fail("", "adjoints", std::to_string(adjoints.size()) + " images for " + std::to_string(expected) + " view(s)");
  const glm::uvec2 pixels = imagePixels(scene.camera);
  const uint32_t layers = scene.gate.layers();
  for (size_t k = 0; k < adjoints.size(); ++k) {
    const ImageSet& a = adjoints[k];
    const std::string field = "adjoints[" + std::to_string(k) + "]";
    if (a.width != pixels.x || a.height != pixels.y || a.layers.size() != layers)
      fail("", field,
           std::to_string(a.width) + "x" + std::to_string(a.height) + " with " + std::to_string(a.layers.size()) +
               " layers, but the render's image is " + std::to_string(pixels.x) + "x" + std::to_string(pixels.y) +
               " with " + std::to_string(layers));
    for (const ImageLayer& layer : a.layers) {
      if (layer.pixels.size() != size_t(pixels.x) * pixels.y) fail("", field, "a layer's pixels do not fill its image");
      for (float v : layer.pixels)
        if (!std::isfinite(v)) fail("", field, "d loss / d I is not finite");
    }
  }
  std::vector<uint32_t> selected;
  for (const std::string& name : parameters) selected.push_back(findParameter(scene, name, "parameters"));
  const ParameterModel parameterModel(scene, selected);
  const std::vector<double> zero(selected.size(), 0.0);
  DeviceScene deviceScene(context.impl().vulkan, parameterModel, zero, zero);
  std::vector<AdjointView> adjointViews;
  const RenderSetup setup = RenderSetup::of(scene);
  if (views.empty()) adjointViews.push_back({setup, {}, &adjoints.front()});
  for (size_t k = 0; k < views.size(); ++k) {
    RenderSetup s = setup;
    s.camera = views[k].camera;
    s.settings.seed = views[k].seed;
    adjointViews.push_back({s, views[k].lightPositions, &adjoints[k]});
  }
  AdjointState state;
  const LossGradient g = lossGradient(context.impl().renderer, deviceScene, adjointViews, gradientOptions(context, request, false), state);
  if (g.stats.nonFinite > 0) throw Error("gradient: " + std::to_string(g.stats.nonFinite) + " non-finite contributions");
  return g.theta;
}

}  // namespace vktg
