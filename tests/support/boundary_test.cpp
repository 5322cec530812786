#include "support/boundary_test.h"

#include "support/grad_test.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "support/gpu_context.h"
#include "support/test_scenes.h"

namespace vktg::test {

void addTranslation(Scene& scene, const std::string& name, const std::string& shape, glm::vec3 axis) {
  Parameter p;
  p.name = name;
  p.kind = ParameterKind::Translate;
  p.target = shape;
  p.axis = axis;
  scene.parameters.push_back(p);
}

void addLightMove(Scene& scene, const std::string& name, const std::string& light, glm::vec3 axis) {
  Parameter p;
  p.name = name;
  p.kind = ParameterKind::LightPosition;
  p.target = light;
  p.axis = axis;
  scene.parameters.push_back(p);
}

void addGateCenter(Scene& scene, const std::string& name) {
  Parameter p;
  p.name = name;
  p.kind = ParameterKind::GateCenter;
  scene.parameters.push_back(p);
}

LayerEstimate layerOf(const ImageSet& mean, const ImageSet& variance, uint32_t layer) {
  LayerEstimate e;
  const auto& m = mean.layers.at(layer).pixels;
  const auto& v = variance.layers.at(layer).pixels;
  e.mean.assign(m.begin(), m.end());
  e.variance.assign(v.begin(), v.end());
  return e;
}

LayerEstimate sumLayers(const std::vector<LayerEstimate>& layers) {
  LayerEstimate s = layers.at(0);
  for (size_t l = 1; l < layers.size(); ++l) {
    for (size_t i = 0; i < s.mean.size(); ++i) {
      s.mean[i] += layers[l].mean[i];
      s.variance[i] += layers[l].variance[i];
      if (layers[l].isUnresolved(i)) {
        s.unresolved.resize(s.mean.size(), false);
        s.unresolved[i] = true;
      }
    }
    s.dof = std::min(s.dof, layers[l].dof);
  }
  return s;
}

LayerEstimate sumPixels(const LayerEstimate& e) {
  LayerEstimate s;
  s.dof = e.dof;
  s.mean = {0.0};
  s.variance = {0.0};
  for (size_t i = 0; i < e.mean.size(); ++i) {
    s.mean[0] += e.mean[i];
    s.variance[0] += e.variance[i];
  }
  return s;
}

LayerEstimate sumTiles(const LayerEstimate& e, size_t width, size_t tile) {
  const size_t height = e.mean.size() / width, tilesAcross = width / tile;
  LayerEstimate s;
  s.dof = e.dof;
  s.mean.assign(tilesAcross * (height / tile), 0.0);
  s.variance.assign(s.mean.size(), 0.0);
  for (size_t i = 0; i < e.mean.size(); ++i) {
    size_t t = (i / width / tile) * tilesAcross + (i % width) / tile;
    s.mean[t] += e.mean[i];
    s.variance[t] += e.variance[i];
  }
  return s;
}

SeedDifference seedFiniteDifference(const Scene& scene, const std::string& parameter, double eps, uint32_t seeds,
                                    const RenderOptions& options) {
  SeedDifference out;
  Scene plus = perturbScene(scene, parameter, eps), minus = perturbScene(scene, parameter, -eps);
  std::vector<std::vector<std::vector<double>>> perSeed;  // [seed][layer][pixel]
  for (uint32_t k = 0; k < seeds; ++k) {
    plus.render.seed = minus.render.seed = scene.render.seed + 1000 * (k + 1);
    RenderResult p = testRenderer().render(plus, options);
    RenderResult m = testRenderer().render(minus, options);
    out.nonFinite += p.stats.nonFinite + m.stats.nonFinite;
    out.seconds += p.stats.seconds + m.stats.seconds;
    std::vector<std::vector<double>> d(p.mean.layers.size());
    for (size_t l = 0; l < d.size(); ++l) {
      const auto& a = p.mean.layers[l].pixels;
      const auto& b = m.mean.layers[l].pixels;
      d[l].resize(a.size());
      for (size_t i = 0; i < a.size(); ++i) d[l][i] = (double(a[i]) - double(b[i])) / (2 * eps);
    }
    perSeed.push_back(std::move(d));
  }
  size_t layers = perSeed[0].size();
  for (size_t l = 0; l < layers; ++l) {
    LayerEstimate e;
    size_t pixels = perSeed[0][l].size();
    e.mean.assign(pixels, 0.0);
    e.variance.assign(pixels, 0.0);
    e.dof = double(seeds) - 1;
    e.unresolved.assign(pixels, false);
    for (size_t i = 0; i < pixels; ++i) {
      double sum = 0, sum2 = 0;
      bool changed = false;
      for (uint32_t k = 0; k < seeds; ++k) {
        sum += perSeed[k][l][i];
        changed = changed || perSeed[k][l][i] != 0.0;
      }
      e.unresolved[i] = !changed;
      double mean = sum / seeds;
      for (uint32_t k = 0; k < seeds; ++k) sum2 += (perSeed[k][l][i] - mean) * (perSeed[k][l][i] - mean);
      e.mean[i] = mean;
      e.variance[i] = sum2 / (double(seeds) - 1) / seeds;
    }
    out.layers.push_back(std::move(e));
  }
  return out;
}

namespace {

// The t threshold at floor(dof) (fewer degrees of freedom: a slightly larger, conservative
// threshold), cached: Welch dof differ per pixel and each quantile costs a bisection.
double thresholdFor(double level, double dof) {
  static std::map<std::pair<double, double>, double> cache;
  double d = dof >= 1e5 ? kNormalDof : std::max(1.0, std::floor(dof));
  auto key = std::make_pair(level, d);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  return cache[key] = studentTwoSidedQuantile(level, d);
}

}  // namespace

PixelCheck checkPixels(const LayerEstimate& a, const LayerEstimate& b, double level) {
  PixelCheck c;
  double worst = -1;
  for (size_t i = 0; i < a.mean.size(); ++i) {
    double va = a.variance[i], vb = b.variance[i];
    double variance = va + vb;
    double diff = a.mean[i] - b.mean[i];
    // Welch-Satterthwaite: the degrees of freedom of a sum of two variance estimates.
    double denom = va * va / a.dof + vb * vb / b.dof;
    double dof = denom > 0 ? variance * variance / denom : kNormalDof;
    double t = variance > 0 ? std::abs(diff) / std::sqrt(variance) : (diff == 0 ? 0.0 : INFINITY);
    double threshold = thresholdFor(level, dof);
    if (t > threshold && (a.isUnresolved(i) || b.isUnresolved(i))) {
      ++c.unresolved;  // not a rejection: one side saw nothing, which says little of rare events
      continue;
    }
    ++c.tested;
    if (t > threshold) ++c.rejected;
    if (t > worst) {
      worst = t;
      std::ostringstream text;
      text << "pixel " << i << ": " << a.mean[i] << " vs " << b.mean[i] << " (se " << std::sqrt(va) << " + "
           << std::sqrt(vb) << ", t = " << t << ", dof " << dof << ", threshold " << threshold << ")";
      c.worst = text.str();
      c.worstT = t;
    }
  }
  return c;
}

LayerEstimate exactLayer(const std::vector<double>& values, double relativeFloor) {
  LayerEstimate e;
  e.mean = values;
  for (double v : values) e.variance.push_back(relativeFloor * v * relativeFloor * v);
  return e;
}

}  // namespace vktg::test
