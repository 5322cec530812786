// The parameters an optimisation moves, as one vector θ (THEORY.md §7): the scene at any θ, the
// tables that let the device move vertices itself, which scene quantities the parameters touch,
// and the chain rule from gradients with respect to those quantities (per vertex, per material,
// emitter, light and the gate) to dℓ/dθ. Gradients cost O(vertices + parameters), never
// O(vertices × parameters): each vertex lists the few parameters that move it.
#pragma once
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/gpu/shared.h"
#include "vktg/scene.h"

namespace vktg {

// Gradients of a scalar (a loss) with respect to the scene quantities parameters can touch.
struct SceneGradient {
  std::vector<glm::dvec3> vertices;   // per vertex, prepareScene order (shapes concatenated)
  std::vector<glm::dvec3> materials;  // per material: (albedo, roughness, ior)
  std::vector<double> emission;       // per shape
  std::vector<double> intensity;      // per point light
  std::vector<glm::dvec3> lightPosition;  // per point light
  double gateCenter = 0;              // a shift of the whole gate towards longer paths

  void resize(const Scene& scene);    // zero-filled, sized for `scene`
};

// Device form of the vertex motion: vertex v applies ops opList[first .. first + count) of
// vertexOps[v] = (first, count) in order; op k is the θ index of a Translate, Rotate or Displace
// parameter, described by parameterOps[k] (unused for the other kinds).
struct VertexOpTables {
  std::vector<glm::uvec2> vertexOps;
  std::vector<uint32_t> opList;
  std::vector<gpu::GpuParameterOp> parameterOps;  // one per θ entry
};

class ParameterModel {
 public:
  // `selected`: indices into scene.parameters; their order is the order of θ.
  ParameterModel(const Scene& scene, std::vector<uint32_t> selected);

  size_t size() const { return m_selected.size(); }
  const Scene& baseScene() const { return m_scene; }  // θ = 0
  // Per vertex (prepareScene order) and per shape: whether some selected parameter moves it.
  std::vector<bool> movingShapes() const;
  const std::vector<uint32_t>& selected() const { return m_selected; }
  const Parameter& parameter(size_t k) const { return m_scene.parameters[m_selected[k]]; }

  // The scene with the selected parameters at θ (applyParameters).
  Scene sceneAt(std::span<const double> theta) const;
  // Sets everything but vertex positions to its value at θ: materials, emission, point lights,
  // the gate (O(parameters that are not vertex motions), no copy of the geometry).
  void setScalars(Scene& scene, std::span<const double> theta) const;
  // The vertices of shape `shape` at θ, in double precision (the same motion as sceneAt).
  std::vector<glm::dvec3> shapePositions(std::span<const double> theta, uint32_t shape) const;

  // What the selected parameters touch. Known from construction: a gradient asks several times,
  // and a scan over 10^6 heights each time cost more than the gradient's device work.
  bool selects(ParameterKind kind) const { return (m_kinds >> uint32_t(kind)) & 1u; }
  bool movesVertices() const { return !m_opList.empty(); }
  // The world axes along which some selected parameter moves a vertex: a translation's or a
  // displacement's nonzero axis components, all three once a rotation is selected.
  glm::bvec3 vertexMotionAxes() const { return m_motionAxes; }
  // A loss gradient keeps per vertex only the components along those axes, in x, y, z order: this
  // many (a flat heightfield's heights: y alone, a third of the accumulators to clear, add to, copy
  // back and scan).
  uint32_t vertexGradientStride() const {
    return uint32_t(m_motionAxes.x) + uint32_t(m_motionAxes.y) + uint32_t(m_motionAxes.z);
  }
  const std::vector<bool>& movingVertices() const { return m_movingVertex; }  // per vertex
  // Per vertex: moved by a displacement (not rigidly with its shape).
  const std::vector<bool>& deformingVertices() const { return m_deformingVertex; }
  bool movesPointLights() const { return selects(ParameterKind::LightPosition); }
  bool touchesMaterials() const {
    return selects(ParameterKind::Albedo) || selects(ParameterKind::Roughness) || selects(ParameterKind::Ior);
  }
  bool touchesEmission() const { return selects(ParameterKind::Emission); }
  bool touchesIntensity() const { return selects(ParameterKind::Intensity); }
  bool touchesGate() const { return selects(ParameterKind::GateCenter); }

  VertexOpTables deviceTables() const;

  // dℓ/dθ at θ from the gradient with respect to scene quantities at θ.
  std::vector<double> chainRule(std::span<const double> theta, const SceneGradient& gradient) const;
  // The same with the vertices' part in fixed point, as a loss gradient's accumulators hold it:
  // vertexGradientStride() values per vertex, the components along vertexMotionAxes() divided by
  // `scale`, the others 0 (bit for bit what converting them to doubles first gives; at 10^6
  // vertices that conversion was a pass of its own over 24 MB). gradient.vertices is not read.
  std::vector<double> chainRule(std::span<const double> theta, const SceneGradient& gradient,
                                std::span<const int64_t> fixed, double scale) const;

 private:
  Scene m_scene;
  std::vector<uint32_t> m_selected;
  std::vector<uint32_t> m_firstVertex;        // per shape: its first vertex in the concatenation
  std::vector<glm::uvec2> m_vertexOps;        // per vertex: (first, count) in m_opList
  std::vector<uint32_t> m_opList;             // θ indices, per vertex in declaration order
  std::vector<bool> m_movingVertex;
  std::vector<bool> m_deformingVertex;
  uint32_t m_kinds = 0;                       // bit k: a parameter of ParameterKind k is selected
  glm::bvec3 m_motionAxes{false};
  // Per θ index: the parameter's axis, w = 1 for a rotation. For a vertex moved by a lone
  // translation or displacement the chain rule reads these 16 bytes instead of the whole Parameter
  // record (names, vertex lists).
  std::vector<glm::vec4> m_motion;
  std::vector<uint32_t> m_scalarParameters;  // θ indices of parameters that move no vertex, declaration order

  std::vector<double> scalarChainRule(std::span<const double> theta, const SceneGradient& gradient) const;
  // Adds every vertex's part, vertex v's gradient being vertexGradient(v) (a glm::dvec3).
  template <class VertexGradient>
  void addVertexChainRule(std::span<const double> theta, VertexGradient vertexGradient, std::vector<double>& out) const;
};

}  // namespace vktg
