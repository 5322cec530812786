// Drivers for derivatives: `vktg grad` (forward-mode lanes through the wavefront passes, in blocks
// of kMaxDerivativeLanes parameters) and `vktg fd` (central finite differences with common random
// numbers, the reference the derivative passes are validated against).
#pragma once
#include <string>
#include <vector>

#include "host/renderer.h"

namespace vktg {

struct GradientResult {
  RenderResult primal;                // the image of the first block (every block renders it)
  std::vector<std::string> parameters;
  std::vector<ImageSet> derivatives;  // per parameter: one layer per gate layer
  std::vector<ImageSet> variances;
  RenderStats stats;                  // summed over blocks
};

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const RenderOptions& options);

struct FiniteDifferenceResult {
  ImageSet derivative;  // (I(θ + eps) - I(θ - eps)) / (2 eps), same seed on both sides
  ImageSet variance;    // bound on its variance: (var+ + var-) / (4 eps^2) (the shared seed only lowers it)
  RenderStats stats;
};

FiniteDifferenceResult finiteDifference(Renderer& renderer, const Scene& scene, const std::string& parameter,
                                        double eps, const RenderOptions& options);

}  // namespace vktg
