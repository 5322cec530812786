#include "render/adjoint.h"

#include <algorithm>
#include <cmath>

#include "vktg/error.h"

namespace vktg {

GradientLayout gradientLayout(const Scene& scene, const PreparedScene& prepared, const ParameterModel& model) {
  GradientLayout l;
  l.materials = 1;  // slot 0: the gate centre
  l.emission = l.materials + 3 * uint32_t(scene.materials.size());
  l.lights = l.emission + uint32_t(scene.shapes.size());
  l.vertices = l.lights + 4 * uint32_t(scene.pointLights.size());
  l.total = l.vertices + model.vertexGradientStride() * uint32_t(prepared.vertices.size());
  return l;
}

uint32_t adjointTargets(const ParameterModel& model) {
  uint32_t bits = 0;
  if (model.movesVertices()) {
    const glm::bvec3 axes = model.vertexMotionAxes();
    bits |= gpu::kAdjointVertices | (axes.x ? gpu::kAdjointVertexX : 0u) | (axes.y ? gpu::kAdjointVertexY : 0u) |
            (axes.z ? gpu::kAdjointVertexZ : 0u);
  }
  if (model.touchesMaterials()) bits |= gpu::kAdjointMaterials;
  if (model.touchesEmission()) bits |= gpu::kAdjointEmission;
  if (model.movesPointLights() || model.touchesIntensity()) bits |= gpu::kAdjointLights;
  if (model.touchesGate()) bits |= gpu::kAdjointGate;
  return bits;
}

GradientAccumulator::GradientAccumulator(const VulkanContext& context, const GradientLayout& layout)
    : m_context(context), m_layout(layout),
      m_buffer(context, uint64_t(layout.total) * sizeof(int64_t), MemoryKind::Device, "adjoint.gradient"),
      m_host(layout.total, 0) {
  if (!m_buffer.hostReadable())
    m_readback = Buffer(context, m_buffer.size(), MemoryKind::Readback, "adjoint.gradient.readback");
}

void GradientAccumulator::zero() { std::fill(m_host.begin(), m_host.end(), 0); }

void GradientAccumulator::recordClear(VkCommandBuffer cmd) const {
  vkCmdFillBuffer(cmd, m_buffer.handle(), 0, VK_WHOLE_SIZE, 0);
}

void GradientAccumulator::recordCopyBack(VkCommandBuffer cmd) const {
  if (!m_readback) return;  // the host reads m_buffer itself
  VkBufferCopy region{0, 0, m_buffer.size()};
  vkCmdCopyBuffer(cmd, m_buffer.handle(), m_readback.handle(), 1, &region);
}

void GradientAccumulator::readBack() {
  (m_readback ? m_readback : m_buffer).download(m_context, m_host.data(), m_host.size() * sizeof(int64_t));
}

double GradientAccumulator::largestMagnitude() const {
  // In integers: one pass at memory speed over 3 values per vertex.
  uint64_t largest = 0;
  for (int64_t v : m_host) largest = std::max(largest, v < 0 ? 0 - uint64_t(v) : uint64_t(v));
  return double(largest);
}

SceneGradient GradientAccumulator::readScalars(const Scene& scene, double scale) const {
  SceneGradient g;
  g.materials.assign(scene.materials.size(), glm::dvec3(0.0));
  g.emission.assign(scene.shapes.size(), 0.0);
  g.intensity.assign(scene.pointLights.size(), 0.0);
  g.lightPosition.assign(scene.pointLights.size(), glm::dvec3(0.0));
  auto at = [&](uint32_t slot) { return double(m_host.at(slot)) / scale; };
  g.gateCenter = at(0);
  for (size_t m = 0; m < g.materials.size(); ++m) {
    uint32_t s = m_layout.materials + 3 * uint32_t(m);
    g.materials[m] = glm::dvec3(at(s), at(s + 1), at(s + 2));
  }
  for (size_t s = 0; s < g.emission.size(); ++s) g.emission[s] = at(m_layout.emission + uint32_t(s));
  for (size_t l = 0; l < g.intensity.size(); ++l) {
    uint32_t s = m_layout.lights + 4 * uint32_t(l);
    g.intensity[l] = at(s);
    g.lightPosition[l] = glm::dvec3(at(s + 1), at(s + 2), at(s + 3));
  }
  return g;
}

std::span<const int64_t> GradientAccumulator::vertexAccumulators() const {
  return std::span<const int64_t>(m_host).subspan(m_layout.vertices);
}

}  // namespace vktg
