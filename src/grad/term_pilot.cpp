#include "grad/term_pilot.h"

#include <chrono>

#include "render/planner.h"

namespace vktg {

TermAllocation runTermPilot(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                            const GradientOptions& options, AdjointState& state,
                            const std::function<uint32_t(uint32_t, size_t)>& seeds) {
  // The path-length boundary's two estimators are timed apart: their paths, costs and variances
  // differ (a heightfield's direct returns reach the gate's jumps only through the camera's).
  struct PilotTerm {
    Term name;
    bool interior, edges, perPixel, fromCamera;
  };
  const PilotTerm terms[] = {{Term::Interior, true, false, false, false},
                             {Term::Edge, false, true, false, false},
                             {Term::PathLength, false, false, true, false},
                             {Term::PathLengthFromCamera, false, false, false, true}};
  const uint32_t spp = views.front().setup.settings.spp;
  std::vector<TermPilotRuns> runs;
  for (const PilotTerm& term : terms) {
    const bool pathLength = term.perPixel || term.fromCamera;
    if ((term.interior && !options.interior) || (term.edges && !options.edges) || (pathLength && !options.pathLength) ||
        (term.perPixel && !options.pathLengthPerPixel) || (term.fromCamera && !options.pathLengthFromCamera))
      continue;
    GradientOptions g = options;
    g.interior = term.interior, g.edges = term.edges, g.pathLength = pathLength;
    g.pathLengthPerPixel = term.perPixel, g.pathLengthFromCamera = term.fromCamera;
    // Every term at the round's samples per pixel, set through the views: the allocation scales
    // from the interior's.
    g.sppEdge = g.sppBoundary = g.sppBoundaryCamera = 0;
    g.sharePaths = false;
    // Round `round` at termPilotSpp(round, spp); round -1 (the first gradient of the term, untimed,
    // at the smaller count) takes the one-time costs: pipelines, buffers.
    auto gradient = [&](int round, double* seconds) {
      std::vector<AdjointView> seeded = views;
      for (size_t v = 0; v < seeded.size(); ++v) {
        seeded[v].setup.settings.seed = seeds(uint32_t(round + 1), v);
        seeded[v].setup.settings.spp = termPilotSpp(round < 0 ? 1u : uint32_t(round), spp);
      }
      const auto start = std::chrono::steady_clock::now();
      LossGradient result = lossGradient(renderer, scene, seeded, g, state);
      if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    };
    const LossGradient warmUp = gradient(-1, nullptr);
    // The planner drops a term that cannot contribute for these parameters and views.
    const GradientPlan& plan = warmUp.plan;
    if (!(term.interior ? plan.interior : term.edges ? plan.edges : term.perPixel ? plan.pathLengthPerPixel : plan.pathLengthFromCamera))
      continue;
    TermPilotRuns run{term.name, {}};
    for (uint32_t round = 0; round < kTermPilotRounds; ++round) {
      TermPilotRound r;
      r.gradient = gradient(int(round), &r.seconds).theta;
      r.spp = termPilotSpp(round, spp);
      run.rounds.push_back(std::move(r));
    }
    runs.push_back(std::move(run));
  }
  return allocateTermSamples(runs, spp);
}

std::vector<std::string> describeAllocation(const TermAllocation& a) {
  std::vector<std::string> lines = a.reasons;
  for (const TermCost& t : a.terms)
    lines.push_back(formatReason("  %s: variance %.3g, %.3g s + %.3g s per gradient at the interior's samples -> %g spp",
                                 termName(t.term), t.variance, t.fixedSeconds, t.sampleSeconds, t.spp));
  if (!a.terms.empty() && (a.sppEdge || a.sppBoundary || a.sppBoundaryCamera))
    lines.push_back(formatReason("  predicted against every term at the interior's samples: variance %.2fx, seconds %.2fx",
                                 a.varianceRatio, a.secondsRatio));
  return lines;
}

}  // namespace vktg
