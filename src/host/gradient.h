// Drivers for derivatives: `vktg grad` (forward-mode lanes through the wavefront passes, in blocks
// of kMaxDerivativeLanes parameters; one render per term) and `vktg fd` (central finite
// differences with common random numbers, the reference the derivative passes are checked by).
#pragma once
#include <string>
#include <vector>

#include "host/renderer.h"

namespace vktg {

enum class AntitheticMode { Auto, On, Off };

struct GradientOptions {
  RenderOptions render;
  bool interior = true;
  bool pathLength = true;           // the planner still drops it when it cannot contribute
  bool edges = true;                // likewise
  uint32_t sppBoundary = 0;         // samples per pixel of the path-length-boundary pass (0: the scene's spp)
  uint32_t sppEdge = 0;             // edge samples per pixel, on average, of the edge pass (0: the scene's spp)
  AntitheticMode antithetic = AntitheticMode::Auto;
};

// What the gradient planner runs and why.
struct GradientPlan {
  bool interior = false;
  bool pathLength = false;            // some path-length-boundary render runs:
  bool pathLengthPerPixel = false;    //   connections from the path's own vertices
  bool pathLengthFromCamera = false;  //   connections from the camera (splatted)
  bool edges = false;
  bool antithetic = false;
  std::vector<std::string> reasons;
};

// Near-delta: a gate this narrow relative to its centre gets antithetic pairs (gaussian: sigma/mu;
// box and truncated gaussian: half their support's width over its centre).
inline constexpr double kNearDeltaSigmaOverMu = 1e-2;

GradientPlan planGradient(const Scene& scene, const std::vector<std::string>& parameters, const GradientOptions& options);

struct TermImages {
  std::vector<ImageSet> derivatives;  // per parameter: one layer per gate layer
  std::vector<ImageSet> variances;
};

struct GradientResult {
  RenderResult primal;                 // the image (from the interior pass, or a plain render)
  std::vector<std::string> parameters;
  TermImages total;                    // sum of the terms that ran
  TermImages interior, edges, pathLength;  // per term (empty when the term did not run)
  GradientPlan plan;
  RenderStats stats;                   // summed over passes and blocks
};

GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const GradientOptions& options);
// The same with every term the planner chooses and default settings.
GradientResult renderGradient(Renderer& renderer, const Scene& scene, const std::vector<std::string>& parameters,
                              const RenderOptions& options);

struct FiniteDifferenceResult {
  ImageSet derivative;  // (I(θ + eps) - I(θ - eps)) / (2 eps), same seed on both sides
  ImageSet variance;    // (var+ + var-) / (4 eps^2): a bound when the shared seed correlates the sides positively
  RenderStats stats;
};

FiniteDifferenceResult finiteDifference(Renderer& renderer, const Scene& scene, const std::string& parameter,
                                        double eps, const RenderOptions& options);

}  // namespace vktg
