#include "vktg/parameter_model.h"

#include <algorithm>
#include <bit>
#include <numeric>

#include "vktg/error.h"

namespace vktg {
namespace {

// A position rounded to float as the scene stores it. Through a volatile: GCC 12 at -O2 drops the
// double -> float -> double round trip here (as if it were value-preserving).
glm::dvec3 roundedToFloat(const glm::dvec3& p) {
  volatile float x = float(p.x), y = float(p.y), z = float(p.z);
  return glm::dvec3(x, y, z);
}

template <typename T>
uint32_t indexOf(const std::vector<T>& items, const std::string& name) {
  for (size_t i = 0; i < items.size(); ++i)
    if (items[i].name == name) return uint32_t(i);
  throw Error("internal: parameter target \"" + name + "\" not in the scene");
}

}  // namespace

void SceneGradient::resize(const Scene& scene) {
  size_t vertexCount = 0;
  for (const Shape& s : scene.shapes) vertexCount += s.positions.size();
  vertices.assign(vertexCount, glm::dvec3(0.0));
  materials.assign(scene.materials.size(), glm::dvec3(0.0));
  emission.assign(scene.shapes.size(), 0.0);
  intensity.assign(scene.pointLights.size(), 0.0);
  lightPosition.assign(scene.pointLights.size(), glm::dvec3(0.0));
  gateCenter = 0;
}

ParameterModel::ParameterModel(const Scene& scene, std::vector<uint32_t> selected)
    : m_scene(scene), m_selected(std::move(selected)) {
  m_firstVertex.assign(scene.shapes.size() + 1, 0);
  for (size_t s = 0; s < scene.shapes.size(); ++s)
    m_firstVertex[s + 1] = m_firstVertex[s] + uint32_t(scene.shapes[s].positions.size());
  const uint32_t vertexCount = m_firstVertex.back();

  // θ indices of vertex-moving parameters in declaration order: a vertex applies its ops in it.
  std::vector<uint32_t> byDeclaration(m_selected.size());
  std::iota(byDeclaration.begin(), byDeclaration.end(), 0u);
  std::stable_sort(byDeclaration.begin(), byDeclaration.end(),
                   [&](uint32_t a, uint32_t b) { return m_selected[a] < m_selected[b]; });
  for (size_t i = 1; i < byDeclaration.size(); ++i)
    if (m_selected[byDeclaration[i]] == m_selected[byDeclaration[i - 1]])
      throw Error("internal: a parameter is selected twice");

  // Counting sort into per-vertex lists (O(vertices + ops)).
  auto forEachMovedVertex = [&](uint32_t k, auto&& visit) {
    const Parameter& p = scene.parameters.at(m_selected[k]);
    if (!vktg::movesVertices(p.kind)) return;
    const uint32_t shape = indexOf(scene.shapes, p.target);
    const uint32_t first = m_firstVertex[shape];
    if (p.kind == ParameterKind::Displace)
      for (uint32_t v : p.vertices) visit(first + v);
    else
      for (uint32_t v = first; v < m_firstVertex[shape + 1]; ++v) visit(v);
  };
  m_vertexOps.assign(vertexCount, glm::uvec2(0));
  for (uint32_t k : byDeclaration) forEachMovedVertex(k, [&](uint32_t v) { m_vertexOps[v].y++; });
  uint32_t total = 0;
  for (glm::uvec2& range : m_vertexOps) {
    range.x = total;
    total += range.y;
    range.y = 0;
  }
  m_opList.resize(total);
  for (uint32_t k : byDeclaration)
    forEachMovedVertex(k, [&](uint32_t v) { m_opList[m_vertexOps[v].x + m_vertexOps[v].y++] = k; });
  for (uint32_t k : byDeclaration)
    if (!vktg::movesVertices(scene.parameters[m_selected[k]].kind)) m_scalarParameters.push_back(k);
  m_movingVertex.assign(vertexCount, false);
  m_deformingVertex.assign(vertexCount, false);
  for (uint32_t v = 0; v < vertexCount; ++v) {
    m_movingVertex[v] = m_vertexOps[v].y > 0;
    for (uint32_t o = m_vertexOps[v].x; o < m_vertexOps[v].x + m_vertexOps[v].y; ++o)
      if (parameter(m_opList[o]).kind == ParameterKind::Displace) m_deformingVertex[v] = true;
  }
  m_motion.resize(size());
  for (size_t k = 0; k < size(); ++k) {
    const Parameter& p = parameter(k);
    m_motion[k] = glm::vec4(p.axis, p.kind == ParameterKind::Rotate ? 1.0f : 0.0f);
    m_kinds |= 1u << uint32_t(p.kind);
    if (p.kind == ParameterKind::Translate || p.kind == ParameterKind::Displace)
      m_motionAxes = glm::bvec3(m_motionAxes.x || p.axis.x != 0.0f, m_motionAxes.y || p.axis.y != 0.0f,
                                m_motionAxes.z || p.axis.z != 0.0f);
  }
  if (selects(ParameterKind::Rotate)) m_motionAxes = glm::bvec3(true);
}

std::vector<bool> ParameterModel::movingShapes() const {
  std::vector<bool> out(m_scene.shapes.size(), false);
  for (size_t s = 0; s < out.size(); ++s)
    for (uint32_t v = m_firstVertex[s]; v < m_firstVertex[s + 1] && !out[s]; ++v) out[s] = m_movingVertex[v];
  return out;
}

Scene ParameterModel::sceneAt(std::span<const double> theta) const {
  if (theta.size() != size()) throw Error("internal: θ has the wrong size");
  std::vector<std::pair<uint32_t, double>> values;
  values.reserve(size());
  for (size_t k = 0; k < size(); ++k) values.emplace_back(m_selected[k], theta[k]);
  return applyParameters(m_scene, values);
}

void ParameterModel::setScalars(Scene& scene, std::span<const double> theta) const {
  if (theta.size() != size()) throw Error("internal: θ has the wrong size");
  scene.materials = m_scene.materials;
  scene.pointLights = m_scene.pointLights;
  scene.gate = m_scene.gate;
  for (size_t s = 0; s < scene.shapes.size(); ++s) scene.shapes[s].emission = m_scene.shapes[s].emission;
  for (uint32_t k : m_scalarParameters) applyParameter(scene, parameter(k), theta[k]);
}

std::vector<glm::dvec3> ParameterModel::shapePositions(std::span<const double> theta, uint32_t shape) const {
  std::vector<glm::dvec3> out;
  const Shape& s = m_scene.shapes.at(shape);
  out.reserve(s.positions.size());
  for (uint32_t i = 0; i < s.positions.size(); ++i) {
    // Each op rounds to float, as applyParameters (and the device) does.
    glm::dvec3 p(s.positions[i]);
    const glm::uvec2 ops = m_vertexOps[m_firstVertex[shape] + i];
    for (uint32_t o = ops.x; o < ops.x + ops.y; ++o) {
      const uint32_t k = m_opList[o];
      p = roundedToFloat(moveVertex(parameter(k), p, theta[k]));
    }
    out.push_back(p);
  }
  return out;
}

VertexOpTables ParameterModel::deviceTables() const {
  VertexOpTables t;
  t.vertexOps = m_vertexOps;
  t.opList = m_opList;
  t.parameterOps.resize(std::max<size_t>(size(), 1));
  for (size_t k = 0; k < size(); ++k) {
    const Parameter& p = parameter(k);
    gpu::GpuParameterOp& op = t.parameterOps[k];
    op.axisKind = glm::vec4(p.axis, std::bit_cast<float>(uint32_t(p.kind)));
    op.center = glm::vec4(p.center, 0.0f);
  }
  return t;
}

std::vector<double> ParameterModel::scalarChainRule(std::span<const double> theta, const SceneGradient& g) const {
  if (theta.size() != size()) throw Error("internal: θ has the wrong size");
  std::vector<double> out(size(), 0.0);
  for (uint32_t k : m_scalarParameters) {
    const Parameter& p = parameter(k);
    switch (p.kind) {
      case ParameterKind::Translate:
      case ParameterKind::Rotate:
      case ParameterKind::Displace: break;  // not scalar: below, per vertex
      case ParameterKind::LightPosition:
        out[k] = glm::dot(g.lightPosition.at(indexOf(m_scene.pointLights, p.target)), glm::dvec3(p.axis));
        break;
      case ParameterKind::Emission: out[k] = g.emission.at(indexOf(m_scene.shapes, p.target)); break;
      case ParameterKind::Intensity: out[k] = g.intensity.at(indexOf(m_scene.pointLights, p.target)); break;
      case ParameterKind::Albedo: out[k] = g.materials.at(indexOf(m_scene.materials, p.target)).x; break;
      case ParameterKind::Roughness: out[k] = g.materials.at(indexOf(m_scene.materials, p.target)).y; break;
      case ParameterKind::Ior: out[k] = g.materials.at(indexOf(m_scene.materials, p.target)).z; break;
      case ParameterKind::GateCenter: out[k] = g.gateCenter; break;
    }
  }
  return out;
}

template <class VertexGradient>
void ParameterModel::addVertexChainRule(std::span<const double> theta, VertexGradient vertexGradient,
                                        std::vector<double>& out) const {
  // The velocity of op i of a vertex: its own motion at the position it acts on, turned by every
  // rotation applied after it.
  std::vector<glm::dvec3> velocity;
  for (size_t s = 0; s + 1 < m_firstVertex.size(); ++s) {
    for (uint32_t v = m_firstVertex[s]; v < m_firstVertex[s + 1]; ++v) {
      const glm::uvec2 ops = m_vertexOps[v];
      if (ops.y == 0) continue;
      const glm::dvec3 g = vertexGradient(v);
      if (g == glm::dvec3(0.0)) continue;
      const glm::vec4 first = m_motion[m_opList[ops.x]];
      if (ops.y == 1 && first.w == 0.0f) {
        // A lone translation or displacement (every height of a heightfield): its velocity is its
        // axis wherever the vertex is, so the position need not be replayed.
        out[m_opList[ops.x]] += glm::dot(g, glm::dvec3(glm::vec3(first)));
        continue;
      }
      glm::dvec3 position(m_scene.shapes[s].positions[v - m_firstVertex[s]]);
      velocity.assign(ops.y, glm::dvec3(0.0));
      for (uint32_t i = 0; i < ops.y; ++i) {
        const uint32_t k = m_opList[ops.x + i];
        const Parameter& p = parameter(k);
        position = roundedToFloat(moveVertex(p, position, theta[k]));
        velocity[i] = p.kind == ParameterKind::Rotate ? glm::cross(glm::dvec3(p.axis), position - glm::dvec3(p.center))
                                                       : glm::dvec3(p.axis);
        for (uint32_t j = 0; j < i; ++j) velocity[j] = turnVector(p, velocity[j], theta[k]);
      }
      for (uint32_t i = 0; i < ops.y; ++i) out[m_opList[ops.x + i]] += glm::dot(g, velocity[i]);
    }
  }
}

std::vector<double> ParameterModel::chainRule(std::span<const double> theta, const SceneGradient& g) const {
  std::vector<double> out = scalarChainRule(theta, g);
  if (m_opList.empty()) return out;
  if (g.vertices.size() != m_vertexOps.size()) throw Error("internal: vertex gradient has the wrong size");
  addVertexChainRule(theta, [&](uint32_t v) { return g.vertices[v]; }, out);
  return out;
}

std::vector<double> ParameterModel::chainRule(std::span<const double> theta, const SceneGradient& g,
                                              std::span<const int64_t> fixed, double scale) const {
  std::vector<double> out = scalarChainRule(theta, g);
  if (m_opList.empty()) return out;
  const uint32_t stride = vertexGradientStride();
  if (fixed.size() != stride * m_vertexOps.size()) throw Error("internal: vertex gradient has the wrong size");
  addVertexChainRule(theta, [&](uint32_t v) {
    const int64_t* f = fixed.data() + stride * size_t(v);
    glm::dvec3 g(0.0);
    for (int axis = 0; axis < 3; ++axis)
      if (m_motionAxes[axis]) g[axis] = double(*f++) / scale;
    return g;
  }, out);
  return out;
}

}  // namespace vktg
