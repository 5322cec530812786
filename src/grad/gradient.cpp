#include "grad/gradient.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "grad/collective.h"
#include "render/frame_uniforms.h"
#include "render/planner.h"
#include "scene/contacts.h"
#include "vktg/error.h"

namespace vktg {
namespace {

void addStats(RenderStats& total, const RenderStats& s) {
  total.paths += s.paths;
  total.extensionRays += s.extensionRays;
  total.shadowRays += s.shadowRays;
  total.endedByGate += s.endedByGate;
  total.endedByRoulette += s.endedByRoulette;
  total.endedByDepth += s.endedByDepth;
  total.nonFinite += s.nonFinite;
  total.ellipsoidQueries += s.ellipsoidQueries;
  total.ellipsoidEmpty += s.ellipsoidEmpty;
  total.silhouetteEdges = std::max(total.silhouetteEdges, s.silhouetteEdges);
  total.edgeSilhouettes += s.edgeSilhouettes;
  total.edgeConnected += s.edgeConnected;
  total.gradientOverflows += s.gradientOverflows;
  total.batches += s.batches;
  total.batchSize = std::max(total.batchSize, s.batchSize);
  total.deviceBytes = std::max(total.deviceBytes, s.deviceBytes);
  total.seconds += s.seconds;
  // How the device read the scene and traversed it: the same for every render of one scene.
  total.bufferChunks = std::max(total.bufferChunks, s.bufferChunks);
  total.sceneTexels = total.sceneTexels || s.sceneTexels;
  total.wideBvh = total.wideBvh || s.wideBvh;
  total.waveTexels = total.waveTexels || s.waveTexels;
}

// Per shape: whether one of `parameters` (scene.parameters indices) moves its vertices.
std::vector<bool> shapesMovedBy(const Scene& scene, const std::vector<uint32_t>& parameters) {
  std::vector<bool> moving(scene.shapes.size(), false);
  for (uint32_t index : parameters) {
    const Parameter& p = scene.parameters.at(index);
    if (!movesVertices(p.kind)) continue;
    for (size_t s = 0; s < scene.shapes.size(); ++s) moving[s] = moving[s] || scene.shapes[s].name == p.target;
  }
  return moving;
}

void addEffects(ParameterEffects& e, ParameterKind kind) {
  e.movesLength |= isGeometric(kind) || kind == ParameterKind::GateCenter;
  e.movesGeometry |= movesVertices(kind);
  e.movesPointLight |= kind == ParameterKind::LightPosition;
}

}  // namespace

ParameterEffects parameterEffects(const Scene& scene, const std::vector<uint32_t>& parameters) {
  ParameterEffects e;
  for (uint32_t index : parameters) addEffects(e, scene.parameters.at(index).kind);
  return e;
}

ParameterEffects parameterEffects(const ParameterModel& model) {
  ParameterEffects e;
  for (uint32_t kind = 0; kind <= uint32_t(ParameterKind::GateCenter); ++kind)
    if (model.selects(ParameterKind(kind))) addEffects(e, ParameterKind(kind));
  return e;
}

GradientPlan planGradient(const Scene& scene, const RenderSetup& setup, const ParameterEffects& effects,
                          const GradientOptions& options) {
  GradientPlan plan;
  plan.interior = options.interior;
  if (plan.interior) plan.reasons.push_back("interior term: derivatives along every sampled path");
  const Gate& gate = setup.gate;
  const uint32_t maxDepth = setup.settings.maxDepth;
  const CameraType camera = setup.camera.type;
  if (!options.pathLength) {
    plan.reasons.push_back("path-length-boundary term: not requested");
  } else if (!gate.hasJumps()) {
    plan.reasons.push_back("no path-length-boundary pass: the gate (" + gate.describe() + ") has no jumps");
  } else if (!effects.movesLength) {
    plan.reasons.push_back("no path-length-boundary pass: no selected parameter changes path lengths or moves the gate");
  } else {
    // A connection from vertex e closes a path of e + 2 segments.
    if (!options.pathLengthPerPixel) {
      plan.reasons.push_back("path-length-boundary connections from path vertices: not requested");
    } else if (maxDepth >= firstEllipsoidVertex(camera) + 2) {
      plan.pathLengthPerPixel = true;
      plan.reasons.push_back("path-length-boundary pass: the gate jumps at " + std::to_string(gate.jumpLocations().size()) +
                             " lengths and parameters move path lengths across them");
    }
    bool emitters = std::any_of(scene.shapes.begin(), scene.shapes.end(), [](const Shape& sh) { return sh.emission > 0; });
    if (!options.pathLengthFromCamera) {
      plan.reasons.push_back("path-length-boundary connections from the camera: not requested");
    } else if (camera == CameraType::Perspective && maxDepth >= 2) {
      plan.pathLengthFromCamera = true;
      plan.reasons.push_back("path-length-boundary connections from the pinhole, splatted: the pixel fixes the first hit, so paths camera -> surface -> light have no other vertex to place on a jump");
    }
    if (options.pathLengthFromCamera && emitters && maxDepth >= 1) {
      plan.pathLengthFromCamera = true;
      plan.reasons.push_back("path-length-boundary connections from the camera to emitters it sees directly, splatted (one-segment paths)");
    }
    plan.pathLength = plan.pathLengthPerPixel || plan.pathLengthFromCamera;
    if (!plan.pathLength)
      plan.reasons.push_back("no path-length-boundary pass: max depth " + std::to_string(maxDepth) +
                             " leaves no path a requested connection could place on a jump");
  }
  bool twoJumps = gate.type == GateType::Box || gate.type == GateType::TruncatedGaussian;
  bool nearDelta = (gate.type == GateType::Gaussian && gate.sigma <= kNearDeltaSigmaOverMu * gate.mu) ||
                   (twoJumps && gate.b - gate.a <= kNearDeltaSigmaOverMu * (gate.a + gate.b));
  plan.antithetic = options.antithetic == AntitheticMode::On ||
                    (options.antithetic == AntitheticMode::Auto && nearDelta);
  std::string why = nearDelta ? "the gate is near-delta (width/centre <= 1e-2)" : "requested";
  if (plan.antithetic && gate.type == GateType::Gaussian) {
    plan.reasons.push_back("antithetic pairs s, 2 mu - s for the ellipsoidal connections: " + why);
  } else if (plan.antithetic && twoJumps && plan.pathLength) {
    plan.reasons.push_back("antithetic pairs in the path-length-boundary pass (both jumps from one set of random numbers): " + why);
  } else if (plan.antithetic) {
    plan.antithetic = false;
    plan.reasons.push_back("no antithetic pairs: they pair the mirrored lengths of a gaussian gate or the two jumps of a box or truncated gaussian in the path-length-boundary pass");
  }
  if (!options.edges) {
    plan.reasons.push_back("edge (visibility-boundary) term: not requested");
  } else if (!effects.movesGeometry && !effects.movesPointLight) {
    plan.reasons.push_back("no edge pass: no selected parameter moves geometry that can occlude or a point light");
  } else {
    plan.edges = true;
    plan.reasons.push_back("edge pass: parameters move geometry or a point light; boundary segments from the camera (primary silhouettes) and behind surfaces at any depth (shadows, occlusion, also seen through glass), the light side at any depth");
  }
  return plan;
}

namespace {

// The renders of a gradient: one per term the plan picks, each with its own options and budget
// (0: the setup's spp). A loss gradient may run the interior and per-pixel path-length-boundary
// terms on one set of paths.
struct TermPass {
  RenderOptions options;  // options.term: which
  double spp;  // samples per pixel, possibly fractional (0: the setup's)

  // The setup and options of this pass's render.
  void apply(RenderSetup& setup) {
    if (!(spp > 0)) return;
    setup.settings.spp = uint32_t(std::ceil(spp));
    if (double(setup.settings.spp) != spp) options.samplesPerPixel = spp;
  }
};

// Whether a loss gradient traces the interior and per-pixel path-length-boundary terms' paths once.
bool sharesPaths(const GradientPlan& plan, const GradientOptions& options, uint32_t spp) {
  return options.sharePaths && plan.interior && plan.pathLengthPerPixel &&
         (options.sppBoundary == 0 || options.sppBoundary == spp);
}

std::vector<TermPass> gradientPasses(const GradientPlan& plan, const Gate& gate, const GradientOptions& options,
                                 bool sharePaths = false) {
  std::vector<TermPass> passes;
  RenderOptions base = options.render;
  // The interior pass pairs mirrored lengths of gaussian gates only; the path-length-boundary
  // pass (two-jump gates) pairs both jumps.
  base.antithetic = plan.antithetic && gate.type == GateType::Gaussian;
  auto of = [](const RenderOptions& options, Term term) {
    RenderOptions o = options;
    o.term = term;
    return o;
  };
  RenderOptions boundary = base;
  boundary.antithetic = plan.antithetic;
  // The interior term's antithetic pairs are for gaussian gates, which have no jumps: the
  // boundary's setting serves both where they share their paths.
  if (sharePaths) passes.push_back({of(boundary, Term::InteriorAndPathLength), 0});
  else if (plan.interior) passes.push_back({base, 0});
  if (plan.edges) passes.push_back({of(base, Term::Edge), options.sppEdge});
  if (plan.pathLengthPerPixel && !sharePaths) passes.push_back({of(boundary, Term::PathLength), options.sppBoundary});
  if (plan.pathLengthFromCamera)
    passes.push_back({of(boundary, Term::PathLengthFromCamera),
                      options.sppBoundaryCamera ? options.sppBoundaryCamera : options.sppBoundary});
  return passes;
}

// A render of `setup`, or of `views` where there are any (setup then gives what they share).
RenderResult renderOf(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup, const std::vector<RenderView>& views,
                      const RenderOptions& options) {
  return views.empty() ? renderer.render(scene, setup, options) : renderer.render(scene, setup, views, options);
}

// Renders one term for every parameter, in blocks of kMaxDerivativeLanes lanes.
TermImages renderTerm(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup,
                      const std::vector<RenderView>& views, const std::vector<ParameterBinding>& bindings,
                      const RenderOptions& options, RenderStats& stats, RenderResult* primal) {
  TermImages term;
  for (size_t first = 0; first < bindings.size(); first += kMaxDerivativeLanes) {
    RenderOptions block = options;
    size_t last = std::min(bindings.size(), first + kMaxDerivativeLanes);
    block.derivativeLanes.assign(bindings.begin() + first, bindings.begin() + last);
    RenderResult r = renderOf(renderer, scene, setup, views, block);
    addStats(stats, r.stats);
    for (size_t k = 0; k < r.derivatives.size(); ++k) {
      term.derivatives.push_back(std::move(r.derivatives[k]));
      term.variances.push_back(std::move(r.derivativeVariances[k]));
    }
    if (first == 0 && primal) *primal = std::move(r);
  }
  return term;
}

// Adds `b` into `a` (variances add: the passes are independent).
void accumulateTerm(TermImages& a, const TermImages& b) {
  if (a.derivatives.empty()) {
    a = b;
    return;
  }
  for (size_t p = 0; p < a.derivatives.size(); ++p)
    for (size_t l = 0; l < a.derivatives[p].layers.size(); ++l)
      for (size_t i = 0; i < a.derivatives[p].layers[l].pixels.size(); ++i) {
        a.derivatives[p].layers[l].pixels[i] += b.derivatives[p].layers[l].pixels[i];
        a.variances[p].layers[l].pixels[i] += b.variances[p].layers[l].pixels[i];
      }
}

std::vector<uint32_t> parameterIndices(const Scene& scene, const std::vector<std::string>& names) {
  std::vector<uint32_t> out;
  for (const std::string& name : names) out.push_back(findParameter(scene, name, "--param"));
  return out;
}

}  // namespace

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const GradientOptions& options, const std::vector<RenderView>& views) {
  if (parameters.empty()) throw Error("--param: no parameters selected");
  std::vector<ParameterBinding> bindings = bindParameters(scene, parameters);
  GradientResult result;
  result.parameters = parameters;
  RenderSetup setup = RenderSetup::of(scene);
  if (!views.empty()) setup.camera = views.front().camera;  // the planner sees the first view
  result.plan = planGradient(scene, setup, parameterEffects(scene, parameterIndices(scene, parameters)), options);
  // One upload of the scene serves every term and block.
  DeviceScene deviceScene(renderer.context(), scene);
  if (result.plan.edges) {
    const std::vector<ShapeContact> contacts = findContacts(
        deviceScene.prepared(), shapesMovedBy(scene, parameterIndices(scene, parameters)), surfaceOffset(deviceScene.prepared()));
    for (std::string& line : describeContacts(scene, contacts)) result.plan.reasons.push_back(std::move(line));
  }
  std::vector<TermPass> passes = gradientPasses(result.plan, scene.gate, options);
  if (!result.plan.interior) {
    RenderOptions plain = options.render;
    plain.antithetic = result.plan.antithetic && scene.gate.type == GateType::Gaussian;
    result.primal = renderOf(renderer, deviceScene, setup, views, plain);
    addStats(result.stats, result.primal.stats);
  }
  for (TermPass& pass : passes) {
    RenderSetup termSetup = setup;
    pass.apply(termSetup);
    TermImages images = renderTerm(renderer, deviceScene, termSetup, views, bindings, pass.options, result.stats,
                                   pass.options.term == Term::Interior ? &result.primal : nullptr);
    accumulateTerm(result.total, images);
    switch (pass.options.term) {
      case Term::Interior: result.interior = std::move(images); break;
      case Term::Edge: result.edges = std::move(images); break;
      case Term::PathLength:
      case Term::PathLengthFromCamera: accumulateTerm(result.pathLength, images); break;
      case Term::InteriorAndPathLength: throw Error("internal: derivative images run their terms apart");
    }
  }
  if (result.total.derivatives.empty()) throw Error("--terms: no derivative term selected");
  return result;
}

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const RenderOptions& options) {
  GradientOptions gradient;
  gradient.render = options;
  return renderGradient(renderer, scene, parameters, gradient);
}

namespace {

// The accumulators hold round(value * scale); aim the largest entry at 2^40 of them: 2^23 of
// headroom below the int64 range, and 40 bits of resolution (far finer than the noise of any
// Monte Carlo gradient) for the largest entries.
constexpr double kTargetBits = 40, kCoarsestBits = 24;
// Renders of one gradient at most: scale corrections after overflow, all-zero or coarse sums.
constexpr int kAttempts = 6;

// Whether one render can hold both views (Renderer::render of RenderViews): the same gate, settings
// but the seed, camera type and image size, and so the same plan.
bool batchable(const AdjointView& a, const AdjointView& b) {
  RenderSettings sa = a.setup.settings, sb = b.setup.settings;
  sa.seed = sb.seed = 0;
  return a.setup.gate == b.setup.gate && sa == sb && a.setup.camera.type == b.setup.camera.type &&
         imagePixels(a.setup.camera) == imagePixels(b.setup.camera);
}

}  // namespace

std::vector<std::vector<size_t>> viewGroups(const std::vector<AdjointView>& views, bool batch) {
  // Views together save fixed costs, which matter for small images only; a cap on a group's pixels
  // keeps its sample counts within a render's limits wherever one view's are.
  constexpr uint64_t kGroupPixels = uint64_t(1) << 20;
  std::vector<std::vector<size_t>> groups;
  for (size_t v = 0; v < views.size(); ++v) {
    const glm::uvec2 size = imagePixels(views[v].setup.camera);
    const uint64_t room = std::max<uint64_t>(1, kGroupPixels / (uint64_t(size.x) * size.y));
    auto fits = [&](const std::vector<size_t>& g) {
      return batch && g.size() < room && batchable(views[g.front()], views[v]);
    };
    auto it = std::find_if(groups.begin(), groups.end(), fits);
    if (it == groups.end()) groups.push_back({v});
    else it->push_back(v);
  }
  return groups;
}

RenderResult renderGroup(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                         const std::vector<size_t>& group, const RenderSetup& setup, const RenderOptions& options) {
  if (group.size() == 1) {
    scene.placePointLights(views[group.front()].lightPositions);
    return renderer.render(scene, setup, options);
  }
  std::vector<RenderView> together;
  for (size_t v : group)
    together.push_back({views[v].setup.camera, views[v].setup.settings.seed, views[v].lightPositions, views[v].setup.pathOffset});
  return renderer.render(scene, setup, together, options);
}

namespace {

double powerOfTwoScale(double largest, double scale) {
  return std::ldexp(scale, int(std::lround(kTargetBits - std::log2(std::max(largest, 1.0)))));
}

// Writes the adjoint images of `group` (stacked as a render of the group stacks its views' images),
// times `factor`, where the device reads them, or to the staging buffer that the group's next render
// copies from (returned; nullptr where the host maps the image's memory). No allocation once the
// buffers have their size, no submission of their own.
const Buffer* writeAdjointImages(VulkanContext& context, AdjointState& state, size_t g, const std::vector<size_t>& group,
                                 const std::vector<const ImageSet*>& adjoints, float factor) {
  std::vector<float> flat;
  for (size_t layer = 0; layer < adjoints[group.front()]->layers.size(); ++layer)
    for (size_t v : group)
      for (float a : adjoints[v]->layers.at(layer).pixels) flat.push_back(a * factor);
  const size_t bytes = std::max<size_t>(16, flat.size() * sizeof(float));
  Buffer& image = grownBuffer(context, state.images[g], bytes, MemoryKind::Device, "adjoint.image");
  Buffer& destination =
      image.mapped() ? image : grownBuffer(context, state.imageStaging[g], image.size(), MemoryKind::Readback, "adjoint.image.staging");
  destination.upload(context, flat.data(), flat.size() * sizeof(float));
  return image.mapped() ? nullptr : &destination;
}

// image := (image × weight + added × addedWeight) / (weight + addedWeight), pixel by pixel.
void mergeImage(ImageSet& image, double weight, const ImageSet& added, double addedWeight) {
  if (added.layers.size() != image.layers.size()) throw Error("internal: a chained pass's image has other layers");
  for (size_t l = 0; l < image.layers.size(); ++l) {
    std::vector<float>& pixels = image.layers[l].pixels;
    const std::vector<float>& more = added.layers[l].pixels;
    if (more.size() != pixels.size()) throw Error("internal: a chained pass's image has another size");
    for (size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = float((double(pixels[i]) * weight + double(more[i]) * addedWeight) / (weight + addedWeight));
  }
}

}  // namespace

LossGradient lossGradient(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                          const GradientOptions& options, AdjointState& state, const AdjointChain* chain) {
  const ParameterModel* model = scene.model();
  if (!model) throw Error("internal: a loss gradient needs a scene with a parameter model");
  VulkanContext& context = renderer.context();
  LossGradient result;
  const ParameterEffects effects = parameterEffects(*model);
  const uint32_t chained = chain ? chain->passes : 1;
  if (chained == 0 || (chain && (chain->images.size() != views.size() || !chain->adjointOf || !chain->seedOf)))
    throw Error("internal: a chained gradient needs its passes, each view's image, its adjoint and its seeds");
  std::vector<GradientPlan> plans;
  std::vector<bool> sharePaths;
  for (const AdjointView& view : views) {
    plans.push_back(planGradient(scene.scene(), view.setup, effects, options));
    // Chained interior passes trace the interior term alone (they render its image).
    sharePaths.push_back(!chain && sharesPaths(plans.back(), options, view.setup.settings.spp));
    if (sharePaths.back())
      plans.back().reasons.push_back(std::string(kSharedPathsReason) + " of the paths (same spp)");
    if (chained > 1 && plans.back().interior) {
      if (view.setup.settings.spp % chained != 0)
        throw Error("gradient: " + std::to_string(chained) + " chained interior passes need samples per pixel divisible by them, not " +
                    std::to_string(view.setup.settings.spp));
      plans.back().reasons.push_back("interior term in " + std::to_string(chained) + " chained passes of " +
                                     std::to_string(view.setup.settings.spp / chained) +
                                     " spp, each weighted by the adjoint of the images rendered before it");
    }
  }
  if (!plans.empty()) result.plan = plans.front();
  const GradientLayout layout = gradientLayout(scene.scene(), scene.prepared(), *model);
  if (!state.accumulator || !(state.accumulator->layout() == layout))
    state.accumulator = std::make_unique<GradientAccumulator>(context, layout);
  // Views a render can hold together go in one group, each with its adjoint images stacked as
  // the render stacks the views' images.
  const std::vector<std::vector<size_t>> groups = viewGroups(views, options.batchViews);
  state.images.resize(std::max(state.images.size(), groups.size()));
  state.imageStaging.resize(state.images.size());
  std::vector<const ImageSet*> given;
  for (const AdjointView& view : views) given.push_back(view.adjoint);
  // The scale this gradient's attempts use. The state takes it only when the gradient is done, so
  // that one stopped part-way (Ctrl-C during a retry) leaves the scale of the last completed
  // gradient, which the checkpoint keeps and from which a resumed run repeats the same attempts.
  // A first scale: contributions are adjoint values times derivatives of sample values, so scale by
  // the largest adjoint value (a power of two, to keep every scale exact).
  double scale = state.scale;
  if (!(scale > 0)) {
    double largestAdjoint = 0;
    for (const AdjointView& view : views)
      for (const ImageLayer& layer : view.adjoint->layers)
        for (float a : layer.pixels) largestAdjoint = std::max(largestAdjoint, double(std::abs(a)));
    if (options.collective) {
      std::vector<double> largest = {largestAdjoint};
      options.collective->max(largest);
      largestAdjoint = largest[0];
    }
    scale = std::ldexp(1.0, int(kTargetBits) - 20 - (largestAdjoint > 0 ? int(std::ceil(std::log2(largestAdjoint))) : 0));
  }
  const uint32_t targets = adjointTargets(*model);
  const double startScale = scale;
  int zeroRetries = 0;
  // The renders of an attempt, in stages: the interior term's passes (one stage each; a stage holds
  // a render per group of views), then every other term. A chain's stages each write the adjoint
  // images they weight by; unchained, the first stage writes the views' own for all.
  struct StageRender {
    size_t group;
    TermPass pass;
    uint32_t stage;
  };
  std::vector<StageRender> renders;
  for (uint32_t stage = 0; stage <= chained; ++stage)
    for (size_t g = 0; g < groups.size(); ++g)
      for (const TermPass& pass : gradientPasses(plans[groups[g].front()], views[groups[g].front()].setup.gate, options,
                                             sharePaths[groups[g].front()])) {
        const bool interior = pass.options.term == Term::Interior || pass.options.term == Term::InteriorAndPathLength;
        if (interior ? stage < chained : stage == chained) renders.push_back({g, pass, stage});
      }
  // A pass that overflowed the accumulators is redone with a coarser scale, one whose largest entry
  // is too coarse with a finer one: both follow from deterministic sums, so a rerun repeats them.
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    result.attempts++;
    RenderStats stats;
    result.passMilliseconds.clear();
    // With a chain: each view's image of every sample so far, its samples per pixel, and the
    // adjoint images the next stage weights by.
    std::vector<ImageSet> images = chain ? chain->images : std::vector<ImageSet>{};
    std::vector<double> imageSpp(views.size(), chain ? double(chain->imageSpp) : 0.0);
    std::vector<ImageSet> adjoints(views.size());
    std::vector<const ImageSet*> current = given;
    std::vector<const Buffer*> staged(groups.size(), nullptr);
    std::vector<AdjointView> chainViews;  // a chain pass's views: its samples and random numbers
    uint32_t written = ~0u;  // the stage whose adjoint images the device holds
    // The first render's commands clear the accumulators and the last one's copy them for the host:
    // a gradient waits on the device once per render and batch, no more.
    for (size_t k = 0; k < renders.size(); ++k) {
      const auto& [g, planned, stage] = renders[k];
      TermPass pass = planned;
      if (written != stage && (written == ~0u || chain)) {
        // A chain's later stages weight by the adjoint of every image so far; its interior passes
        // each take 1 / chained of the gradient, with samples and random numbers of their own.
        if (chain && stage > 0) {
          for (size_t v = 0; v < views.size(); ++v) adjoints[v] = chain->adjointOf(v, images[v]);
          for (size_t v = 0; v < views.size(); ++v) current[v] = &adjoints[v];
        }
        const float factor = stage < chained ? 1.0f / float(chained) : 1.0f;
        for (size_t h = 0; h < groups.size(); ++h) staged[h] = writeAdjointImages(context, state, h, groups[h], current, factor);
        if (chain && stage < chained) {
          chainViews = views;
          for (size_t v = 0; v < views.size(); ++v) {
            chainViews[v].setup.settings.spp /= chained;
            chainViews[v].setup.settings.seed = chain->seedOf(v, stage);
          }
        }
        written = stage;
      }
      const bool chainPass = chain && stage < chained;
      const std::vector<AdjointView>& stageViews = chainPass ? chainViews : views;
      AdjointTarget target{&state.images[g], state.accumulator.get(), scale, targets, k == 0, k + 1 == renders.size(),
                           std::exchange(staged[g], nullptr), chainPass};
      RenderSetup termSetup = stageViews[groups[g].front()].setup;
      pass.apply(termSetup);
      pass.options.adjoint = &target;
      const RenderResult r = renderGroup(renderer, scene, stageViews, groups[g], termSetup, pass.options);
      addStats(stats, r.stats);
      for (const auto& [name, ms] : r.passMilliseconds) result.passMilliseconds[std::string(termName(pass.options.term)) + "/" + name] += ms;
      if (target.renderImage) {
        const std::vector<ImageSet> split = splitViews(r.mean, groups[g].size());
        for (size_t i = 0; i < groups[g].size(); ++i) {
          const size_t v = groups[g][i];
          const double spp = termSetup.settings.spp;
          mergeImage(images[v], imageSpp[v], split[i], spp);
          imageSpp[v] += spp;
        }
      }
    }
    // Spread over processes: every decision below is taken on the sum of all of them.
    if (options.collective) sumStats(*options.collective, stats);
    result.stats = stats;
    if (stats.gradientOverflows > 0) {
      scale = std::ldexp(scale, -20);
      continue;
    }
    if (renders.empty()) state.accumulator->zero();  // no term can contribute
    else state.accumulator->readBack();
    if (options.collective) {
      // Integer sums modulo 2^64, as the device's atomic adds wrap: the same bits whichever
      // process added which samples.
      const std::span<int64_t> sums = state.accumulator->hostAccumulators();
      options.collective->sumWrapping(std::span<uint64_t>(reinterpret_cast<uint64_t*>(sums.data()), sums.size()));
    }
    const double largest = state.accumulator->largestMagnitude();
    // All zero: either no sample depends on θ, or every contribution rounded to 0 at this scale.
    // Two much finer scales tell them apart; a gradient still zero then is one.
    if (largest == 0 && zeroRetries < 2 && attempt + 1 < kAttempts) {
      ++zeroRetries;
      scale = std::ldexp(scale, 30);
      continue;
    }
    if (largest == 0) scale = startScale;
    const double next = powerOfTwoScale(largest, scale);
    const bool tooCoarse = largest > 0 && largest < std::ldexp(1.0, int(kCoarsestBits));
    if (tooCoarse && attempt + 1 < kAttempts) {
      scale = next;
      continue;
    }
    state.scale = largest > 0 ? next : scale;
    result.theta = model->chainRule(scene.theta(), state.accumulator->readScalars(scene.scene(), scale),
                                    state.accumulator->vertexAccumulators(), scale);
    result.images = std::move(images);
    return result;
  }
  throw Error("gradient: the accumulators overflowed at every scale tried (a non-finite or huge contribution?)");
}

FiniteDifferenceResult finiteDifference(Renderer& renderer, const Scene& scene, const std::string& parameter,
                                        double eps, const RenderOptions& options, const std::vector<RenderView>& views) {
  if (!(eps > 0)) throw Error("--eps: must be a positive step");
  findParameter(scene, parameter, "--param");
  auto renderAt = [&](double step) {
    const Scene perturbed = perturbScene(scene, parameter, step);
    DeviceScene device(renderer.context(), perturbed);
    return renderOf(renderer, device, RenderSetup::of(perturbed), views, options);
  };
  RenderResult plus = renderAt(eps);
  RenderResult minus = renderAt(-eps);
  FiniteDifferenceResult fd;
  fd.derivative = plus.mean;
  fd.variance = plus.variance;
  for (size_t l = 0; l < fd.derivative.layers.size(); ++l) {
    auto& d = fd.derivative.layers[l].pixels;
    auto& v = fd.variance.layers[l].pixels;
    const auto& m = minus.mean.layers[l].pixels;
    const auto& mv = minus.variance.layers[l].pixels;
    for (size_t i = 0; i < d.size(); ++i) {
      d[i] = float((double(d[i]) - double(m[i])) / (2 * eps));
      v[i] = float((double(v[i]) + double(mv[i])) / (4 * eps * eps));
    }
  }
  addStats(fd.stats, plus.stats);
  addStats(fd.stats, minus.stats);
  return fd;
}

}  // namespace vktg
