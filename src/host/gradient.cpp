#include "host/gradient.h"

#include <algorithm>

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
  total.batches += s.batches;
  total.batchSize = std::max(total.batchSize, s.batchSize);
  total.deviceBytes = std::max(total.deviceBytes, s.deviceBytes);
  total.seconds += s.seconds;
}

}  // namespace

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const RenderOptions& options) {
  if (parameters.empty()) throw Error("--param: no parameters selected");
  std::vector<ParameterBinding> bindings = bindParameters(scene, parameters);
  GradientResult result;
  result.parameters = parameters;
  for (size_t first = 0; first < bindings.size(); first += kMaxDerivativeLanes) {
    RenderOptions block = options;
    size_t last = std::min(bindings.size(), first + kMaxDerivativeLanes);
    block.derivativeLanes.assign(bindings.begin() + first, bindings.begin() + last);
    RenderResult r = renderer.render(scene, block);
    addStats(result.stats, r.stats);
    for (size_t k = 0; k < r.derivatives.size(); ++k) {
      result.derivatives.push_back(std::move(r.derivatives[k]));
      result.variances.push_back(std::move(r.derivativeVariances[k]));
    }
    if (first == 0) result.primal = std::move(r);
  }
  return result;
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
