// Gradients of a loss by adjoint-weighted accumulation (THEORY.md §7): every sample adds
// (d loss / d I of its pixel) × (its contribution's derivative) into one accumulator per scene
// quantity it touches: the gate, per material (albedo, roughness, ior), per shape's emission, per
// point light (intensity, position) and per vertex (position). Accumulators are 64-bit integers
// holding round(value × scale): integer addition is associative, so the sum does not depend on
// the order the device adds in, and a run is reproducible bit for bit (what `--resume` needs).
#pragma once
#include <cstdint>
#include <span>

#include "vk/vk_resources.h"
#include "vktg/parameter_model.h"
#include "vktg/prepared_scene.h"

namespace vktg {

// Where each quantity's accumulators start (in int64 slots), as FrameUniforms.gradientLayout.
struct GradientLayout {
  uint32_t materials = 1, emission = 1, lights = 1, vertices = 1, total = 1;
  bool operator==(const GradientLayout&) const = default;
};

// Vertices hold model.vertexGradientStride() accumulators each (lib/adjoint.glsl, scatterVertex).
GradientLayout gradientLayout(const Scene& scene, const PreparedScene& prepared, const ParameterModel& model);

// kAdjoint* bits (include/vktg/gpu/shared.h): what `model`'s parameters touch.
uint32_t adjointTargets(const ParameterModel& model);

class GradientAccumulator {
 public:
  GradientAccumulator(const VulkanContext& context, const GradientLayout& layout);
  // The device's accumulators are cleared and copied for the host by the renders of a gradient, in
  // their own commands (no submission of their own): the clear before the first render's first pass,
  // the copy after the last one's last. readBack() takes the host's copy once that submission has
  // finished; read() and largestMagnitude() use it. zero(): the host's copy of a gradient no render
  // contributed to.
  void recordClear(VkCommandBuffer cmd) const;
  void recordCopyBack(VkCommandBuffer cmd) const;
  void readBack();
  void zero();
  // The accumulated gradient, divided by `scale`, with respect to `scene`'s quantities but its
  // vertices, whose accumulators ParameterModel::chainRule reads as they are (vertexAccumulators).
  SceneGradient readScalars(const Scene& scene, double scale) const;
  std::span<const int64_t> vertexAccumulators() const;
  // The host's copy of every accumulator, to add other processes' sums into (grad/collective.h).
  std::span<int64_t> hostAccumulators() { return m_host; }
  // The largest accumulator magnitude, in units of the accumulator (to choose the next scale).
  double largestMagnitude() const;
  Buffer& buffer() { return m_buffer; }
  const GradientLayout& layout() const { return m_layout; }

 private:
  const VulkanContext& m_context;
  GradientLayout m_layout;
  Buffer m_buffer;
  // Where the host reads the accumulators through when it cannot read m_buffer directly: made once,
  // since at 10^6 parameters (24 MB) an allocation per gradient costs about what a render does.
  Buffer m_readback;
  std::vector<int64_t> m_host;
};

}  // namespace vktg
