#include "host/term_pilot.h"

#include <chrono>

#include "host/bench_common.h"

namespace vktg {

TermAllocation runTermPilot(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                            const GradientOptions& options, AdjointState& state,
                            const std::function<uint32_t(uint32_t, size_t)>& seeds) {
  struct Term {
    const char* name;
    bool interior, edges, pathLength;
  };
  const Term terms[] = {{"interior", true, false, false}, {"edges", false, true, false}, {"boundary", false, false, true}};
  std::vector<TermPilotRuns> runs;
  for (const Term& term : terms) {
    if ((term.interior && !options.interior) || (term.edges && !options.edges) || (term.pathLength && !options.pathLength))
      continue;
    GradientOptions g = options;
    g.interior = term.interior, g.edges = term.edges, g.pathLength = term.pathLength;
    // Every term at the interior term's samples: the allocation scales from there.
    g.sppEdge = g.sppBoundary = 0;
    g.sharePaths = false;
    TermPilotRuns run{term.name, {}, 0.0};
    std::vector<double> seconds;
    for (uint32_t round = 0; round < kTermPilotRounds; ++round) {
      std::vector<AdjointView> seeded = views;
      for (size_t v = 0; v < seeded.size(); ++v) seeded[v].setup.settings.seed = seeds(round, v);
      const auto start = std::chrono::steady_clock::now();
      LossGradient gradient = lossGradient(renderer, scene, seeded, g, state);
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      const bool ran = term.interior ? gradient.plan.interior : term.edges ? gradient.plan.edges : gradient.plan.pathLength;
      if (!ran) break;  // the planner drops this term for these parameters and views
      run.gradients.push_back(std::move(gradient.theta));
    }
    run.seconds = median(seconds);
    if (run.gradients.size() == kTermPilotRounds) runs.push_back(std::move(run));
  }
  return allocateTermSamples(runs, views.front().setup.settings.spp);
}

}  // namespace vktg
