// The term pilot of `vktg optimize` ("spp_edge" / "spp_boundary": "auto"): a few loss gradients of
// each term at the current θ, timed, from which opt/term_allocation.h sets the terms' samples.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "host/gradient.h"
#include "opt/term_allocation.h"

namespace vktg {

// Runs the pilot at the current θ of `scene`: kTermPilotRounds loss gradients of each term the
// planner picks for `views`, term by term, with seeds `seeds(round)` for every view (independent of
// the optimisation's), then allocates.
TermAllocation runTermPilot(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                            const GradientOptions& options, AdjointState& state,
                            const std::function<uint32_t(uint32_t round, size_t view)>& seeds);

}  // namespace vktg
