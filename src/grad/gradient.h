// Drivers for derivatives: `vktg grad` (forward-mode lanes through the wavefront passes, in blocks
// of kMaxDerivativeLanes parameters; one render per term), the gradient of a loss (the adjoint form
// of the same terms: one render per term and target whatever the number of parameters), and
// `vktg fd` (central finite differences with common random numbers, the reference the derivative
// passes are checked by).
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/renderer.h"

namespace vktg {

class Collective;

enum class AntitheticMode { Auto, On, Off };

struct GradientOptions {
  RenderOptions render;
  bool interior = true;
  bool pathLength = true;           // the planner still drops it when it cannot contribute
  // Which of the path-length-boundary term's two estimators run (the term pilot times them apart):
  // connections from the paths' own vertices (per pixel), and from the camera (splatted).
  bool pathLengthPerPixel = true, pathLengthFromCamera = true;
  bool edges = true;                // likewise
  // Samples per pixel of the other terms' passes, on average: fractional counts (the term pilot's)
  // in loss gradients only, whose per-pixel passes then spread their paths over the pixels.
  double sppBoundary = 0;           // of the path-length-boundary pass (0: the scene's spp)
  double sppBoundaryCamera = 0;     // of its connections from the camera (0: sppBoundary's)
  double sppEdge = 0;               // edge samples per pixel of the edge pass (0: the scene's spp)
  AntitheticMode antithetic = AntitheticMode::Auto;
  // Loss gradients: the interior and per-pixel path-length-boundary terms from one trace of the
  // paths when both run at the same spp (false: a trace each, the same sum; for comparisons).
  bool sharePaths = true;
  // Loss gradients: views that differ only in camera pose, point lights and seed render together,
  // a render per term for all of them (false: a render per term and view; the same gradient).
  bool batchViews = true;
  // Loss gradients spread over processes (grad/collective.h): the views are this process's share,
  // and its accumulators, statistics and scale decisions are those of every process's sum, so each
  // gets the gradient of all the views, the bits one process would get. Null: one process.
  Collective* collective = nullptr;
};

// What the gradient planner runs and why.
struct GradientPlan {
  bool interior = false;
  bool pathLength = false;            // some path-length-boundary render runs:
  bool pathLengthPerPixel = false;    //   connections from the path's own vertices
  bool pathLengthFromCamera = false;  //   connections from the camera (splatted)
  bool edges = false;
  bool antithetic = false;
  std::vector<std::string> reasons;
};

// The plan's reason a loss gradient gives for tracing the interior and per-pixel path-length-boundary
// terms' paths once.
inline constexpr const char* kSharedPathsReason = "interior and per-pixel path-length-boundary terms from one trace";

// Near-delta: a gate this narrow relative to its centre gets antithetic pairs (gaussian: sigma/mu;
// box and truncated gaussian: half their support's width over its centre).
inline constexpr double kNearDeltaSigmaOverMu = 1e-2;

// What the parameters being differentiated do, as far as the planner cares.
struct ParameterEffects {
  bool movesLength = false;      // some parameter changes path lengths or the gate's position
  bool movesGeometry = false;    // some parameter moves vertices
  bool movesPointLight = false;  // some parameter moves a point light
};
ParameterEffects parameterEffects(const Scene& scene, const std::vector<uint32_t>& parameters);
// The same for a loss gradient's parameters (O(1): the model knows which kinds it holds).
ParameterEffects parameterEffects(const ParameterModel& model);

// The terms a gradient of `scene` seen as `setup` says (camera, gate, max depth) needs.
GradientPlan planGradient(const Scene& scene, const RenderSetup& setup, const ParameterEffects& effects,
                          const GradientOptions& options);

struct TermImages {
  std::vector<ImageSet> derivatives;  // per parameter: one layer per gate layer
  std::vector<ImageSet> variances;
};

struct GradientResult {
  RenderResult primal;                 // the image (from the interior pass, or a plain render)
  std::vector<std::string> parameters;
  TermImages total;                    // sum of the terms that ran
  TermImages interior, edges, pathLength;  // per term (empty when the term did not run)
  GradientPlan plan;
  RenderStats stats;                   // summed over passes and blocks
};

// With `views` (a scan's, Renderer::render of RenderViews), every render holds all of them, and
// each image holds the views' images one below the other.
GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const GradientOptions& options, const std::vector<RenderView>& views = {});
// The same with every term the planner chooses and default settings.
GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const RenderOptions& options);

struct FiniteDifferenceResult {
  ImageSet derivative;  // (I(θ + eps) - I(θ - eps)) / (2 eps), same seed on both sides
  ImageSet variance;    // (var+ + var-) / (4 eps^2): a bound when the shared seed correlates the sides positively
  RenderStats stats;
};

// One target of a loss: how it is seen and d loss / d image (the adjoint image, laid out as the
// render's image: one layer per gate layer).
struct AdjointView {
  RenderSetup setup;                                           // camera, gate, spp and seed of the interior pass
  std::vector<std::pair<uint32_t, glm::vec3>> lightPositions;  // point lights moved for this view
  const ImageSet* adjoint = nullptr;
};

// The views in groups that one render can hold (Renderer::render of RenderViews: the same gate,
// settings but the seed, camera type and image size; at most 2^20 pixels in all), each group in
// order; one view per group unless `batch`.
std::vector<std::vector<size_t>> viewGroups(const std::vector<AdjointView>& views, bool batch);

// One render of the views `group` of `views` (a group of viewGroups): `setup` gives the gate and
// settings, each view its camera, seed and point lights. A group of one is a plain one-view render
// of `setup` with the view's point lights placed; its image is the view's, where a larger group's
// stacks them (splitViews).
RenderResult renderGroup(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                         const std::vector<size_t>& group, const RenderSetup& setup, const RenderOptions& options);

// What persists between the gradients of an optimisation: the accumulators and their scale (chosen
// from the previous gradient's magnitude, so the fixed point keeps about 40 bits below the largest
// entry; it is part of a checkpoint).
struct AdjointState {
  std::unique_ptr<GradientAccumulator> accumulator;
  double scale = 0;  // 0: not chosen yet
  // Per group of views rendered together (viewGroups): its adjoint images on the device, and where
  // the host writes them when it cannot map that memory. Kept between gradients, grow-only.
  std::vector<Buffer> images, imageStaging;
};

struct LossGradient {
  std::vector<double> theta;  // d loss / d θ for the model's parameters
  GradientPlan plan;
  RenderStats stats;
  uint32_t attempts = 0;      // renders of the whole gradient (more than one when the scale was refined)
  // With options.render.profile: device time per pass of the last attempt, summed over views, keyed
  // "term/pass" (the term names of termName).
  std::map<std::string, double> passMilliseconds;
  // With an AdjointChain: each view's image from all its samples (the chain's images and every
  // interior pass), the one the loss is best read from.
  std::vector<ImageSet> images;
};

// Chained interior passes (docs/theory.md, "Chained interior passes"): the interior term in
// `passes` renders of spp / passes samples per pixel each (random numbers seedOf(view, pass)), each
// weighted by the adjoint image of every image rendered before it (the views' `images`, then the
// interior passes before it), and adding its own paths' values to those images. The other terms
// then weight by the adjoint of all of them. No render is weighted by an image of its own paths, so
// the gradient is as unbiased as with an independent render, and the render the loss comes from can
// take a fraction of the samples.
struct AdjointChain {
  uint32_t passes = 1;
  std::vector<ImageSet> images;  // per view: the image rendered before the gradient (the views' adjoints are its)
  uint32_t imageSpp = 0;         // its samples per pixel
  std::function<ImageSet(size_t view, const ImageSet& image)> adjointOf;  // d loss / d I of a view's image
  std::function<uint32_t(size_t view, uint32_t pass)> seedOf;             // none the images' own
};

// d loss / d θ = sum over views and pixels of adjoint × d image / d θ, by adjoint renders of every
// term the planner picks (options: terms, spp per term via sppBoundary / sppEdge; the interior term
// uses each view's setup.settings.spp). `scene` must carry the ParameterModel of θ.
LossGradient lossGradient(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                          const GradientOptions& options, AdjointState& state, const AdjointChain* chain = nullptr);

// With `views`, both sides render all of them, as renderGradient does.
FiniteDifferenceResult finiteDifference(Renderer& renderer, const Scene& scene, const std::string& parameter,
                                        double eps, const RenderOptions& options, const std::vector<RenderView>& views = {});

}  // namespace vktg
