#include "host/gradient.h"

#include <algorithm>

#include "host/planner.h"
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
  total.batches += s.batches;
  total.batchSize = std::max(total.batchSize, s.batchSize);
  total.deviceBytes = std::max(total.deviceBytes, s.deviceBytes);
  total.seconds += s.seconds;
}

}  // namespace

GradientPlan planGradient(const Scene& scene, const std::vector<std::string>& parameters, const GradientOptions& options) {
  GradientPlan plan;
  std::vector<ParameterBinding> bindings = bindParameters(scene, parameters);
  bool movesLength = false;  // some parameter changes path lengths or the gate's position
  bool movesGeometry = false, movesPointLight = false;
  for (const ParameterBinding& b : bindings) {
    movesLength |= isGeometric(b.kind) || b.kind == ParameterKind::GateCenter;
    movesGeometry |= isGeometric(b.kind) && b.kind != ParameterKind::LightPosition;
    movesPointLight |= b.kind == ParameterKind::LightPosition;
  }
  plan.interior = options.interior;
  if (plan.interior) plan.reasons.push_back("interior term: forward mode through every sampled path");
  const Gate& gate = scene.gate;
  if (!options.pathLength) {
    plan.reasons.push_back("path-length-boundary term: not requested");
  } else if (!gate.hasJumps()) {
    plan.reasons.push_back("no path-length-boundary pass: the gate (" + gate.describe() + ") has no jumps");
  } else if (!movesLength) {
    plan.reasons.push_back("no path-length-boundary pass: no selected parameter changes path lengths or moves the gate");
  } else {
    // A connection from vertex e closes a path of e + 2 segments.
    if (scene.render.maxDepth >= firstEllipsoidVertex(scene.camera.type) + 2) {
      plan.pathLengthPerPixel = true;
      plan.reasons.push_back("path-length-boundary pass: the gate jumps at " + std::to_string(gate.jumpLocations().size()) +
                             " lengths and parameters move path lengths across them");
    }
    bool emitters = std::any_of(scene.shapes.begin(), scene.shapes.end(), [](const Shape& sh) { return sh.emission > 0; });
    if (scene.camera.type == CameraType::Perspective && scene.render.maxDepth >= 2) {
      plan.pathLengthFromCamera = true;
      plan.reasons.push_back("path-length-boundary connections from the pinhole, splatted: the pixel fixes the first hit, so paths camera -> surface -> light have no other vertex to place on a jump");
    }
    if (emitters && scene.render.maxDepth >= 1) {
      plan.pathLengthFromCamera = true;
      plan.reasons.push_back("path-length-boundary connections from the camera to emitters it sees directly, splatted (one-segment paths)");
    }
    plan.pathLength = plan.pathLengthPerPixel || plan.pathLengthFromCamera;
    if (!plan.pathLength)
      plan.reasons.push_back("no path-length-boundary pass: max depth " + std::to_string(scene.render.maxDepth) +
                             " leaves no path a connection could place on a jump");
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
  } else if (!movesGeometry && !movesPointLight) {
    plan.reasons.push_back("no edge pass: no selected parameter moves geometry that can occlude or a point light");
  } else {
    plan.edges = true;
    plan.reasons.push_back("edge pass: parameters move geometry or a point light; boundary segments from the camera (primary silhouettes) and behind surfaces at any depth (shadows, occlusion), the light side at any depth");
    bool glass = std::any_of(scene.materials.begin(), scene.materials.end(),
                             [](const Material& m) { return m.type == MaterialType::Dielectric; });
    if (glass)
      plan.reasons.push_back("edge pass: its camera side does not continue through dielectrics, so boundary segments the camera sees only through refraction are not sampled (their derivative misses that part)");
  }
  return plan;
}

namespace {

// Renders one term for every parameter, in blocks of kMaxDerivativeLanes lanes.
TermImages renderTerm(Renderer& renderer, const Scene& scene, const std::vector<ParameterBinding>& bindings,
                      const RenderOptions& options, RenderStats& stats, RenderResult* primal) {
  TermImages term;
  for (size_t first = 0; first < bindings.size(); first += kMaxDerivativeLanes) {
    RenderOptions block = options;
    size_t last = std::min(bindings.size(), first + kMaxDerivativeLanes);
    block.derivativeLanes.assign(bindings.begin() + first, bindings.begin() + last);
    RenderResult r = renderer.render(scene, block);
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

}  // namespace

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const GradientOptions& options) {
  if (parameters.empty()) throw Error("--param: no parameters selected");
  std::vector<ParameterBinding> bindings = bindParameters(scene, parameters);
  GradientResult result;
  result.parameters = parameters;
  result.plan = planGradient(scene, parameters, options);
  RenderOptions base = options.render;
  // The interior pass pairs mirrored lengths of gaussian gates only; the path-length-boundary
  // pass (two-jump gates) turns the pairs on below.
  base.antithetic = result.plan.antithetic && scene.gate.type == GateType::Gaussian;
  if (result.plan.interior) {
    result.interior = renderTerm(renderer, scene, bindings, base, result.stats, &result.primal);
    accumulateTerm(result.total, result.interior);
  } else {
    result.primal = renderer.render(scene, base);
    addStats(result.stats, result.primal.stats);
  }
  // A boundary term: its own render with its own budget (0: the scene's spp).
  auto boundaryTerm = [&](uint32_t spp, const RenderOptions& term) {
    Scene termScene = scene;
    if (spp > 0) termScene.render.spp = spp;
    TermImages out = renderTerm(renderer, termScene, bindings, term, result.stats, nullptr);
    accumulateTerm(result.total, out);
    return out;
  };
  if (result.plan.edges) {
    RenderOptions term = base;
    term.edges = true;
    result.edges = boundaryTerm(options.sppEdge, term);
  }
  if (result.plan.pathLength) {
    RenderOptions term = base;
    term.pathLengthBoundary = true;
    term.antithetic = result.plan.antithetic;
    if (result.plan.pathLengthPerPixel) accumulateTerm(result.pathLength, boundaryTerm(options.sppBoundary, term));
    if (result.plan.pathLengthFromCamera) {
      term.pathLengthFromCamera = true;
      accumulateTerm(result.pathLength, boundaryTerm(options.sppBoundary, term));
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

FiniteDifferenceResult finiteDifference(Renderer& renderer, const Scene& scene, const std::string& parameter,
                                        double eps, const RenderOptions& options) {
  if (!(eps > 0)) throw Error("--eps: must be a positive step");
  findParameter(scene, parameter, "--param");
  RenderResult plus = renderer.render(perturbScene(scene, parameter, eps), options);
  RenderResult minus = renderer.render(perturbScene(scene, parameter, -eps), options);
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
