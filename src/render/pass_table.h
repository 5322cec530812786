// Which passes a render runs: one row per term (plan/terms.h), one column per mode. Renderer reads
// everything it needs to know about a term from here (the shaders, the pass labels of the profile,
// what the term needs of the render) instead of from flags.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

#include "plan/terms.h"

namespace vktg {

// How a render differentiates: not at all (the image), forward-mode lanes (derivative images per
// parameter) or the adjoint form (the gradient of a loss, given d loss / d I).
enum class RenderMode : uint32_t { Primal, Forward, Adjoint };
inline constexpr size_t kRenderModes = 3;

const char* renderModeName(RenderMode mode);

struct TermPasses {
  Term term;
  // Modes the term exists in: the boundary terms are derivatives only, the shared trace adjoint only.
  bool primal, forward, adjoint;
  bool needsJumps;   // the gate must have jumps (the path-length-boundary terms)
  // Splatted: each sample owns two path slots and lands in the pixels its camera connections reach
  // (resolve divides by the samples of the view); otherwise paths per pixel.
  bool splat;
  // Extends paths through the per-depth loop; false: its first pass queues complete connections,
  // whose shadow rays are all it traces.
  bool bounces;
  // The first pass already found the hit at the end of every first segment (no depth-0 intersect).
  bool firstHitKnown;
  // The first pass is run a sampling strategy at a time, over the samples sorted to each.
  bool strategies;
  uint32_t specTerm;            // the kSpecTerm value of its passes
  bool cameraConnections;       // kSpecCameraConnections
  const char* sampleOption;     // the option that sets its samples per pixel, named in its errors
  // Per mode (RenderMode order): the pass that starts the samples, the shading and shadow-ray
  // passes of the per-depth loop, and what ends a batch ("" where the mode has none).
  std::array<const char*, kRenderModes> start, shade, shadow, finish;

  bool has(RenderMode mode) const;
};

const TermPasses& termPasses(Term term);

}  // namespace vktg
