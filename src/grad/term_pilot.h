// The term pilot of `vktg optimize` ("spp_edge", "spp_boundary", "spp_boundary_camera": "auto"): a
// few loss gradients of each term at the current θ, timed, from which opt/term_allocation.h sets the
// terms' samples.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "grad/gradient.h"
#include "plan/term_allocation.h"

namespace vktg {

// Runs the pilot at the current θ of `scene`: for each term the planner picks for `views`, an
// untimed first gradient, then kTermPilotRounds timed ones at termPilotSpp samples; the view's seed
// of gradient r (0 the untimed one) is `seeds(r, view)`, independent of the optimisation's. Then
// allocates.
TermAllocation runTermPilot(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                            const GradientOptions& options, AdjointState& state,
                            const std::function<uint32_t(uint32_t round, size_t view)>& seeds);

// The allocation's lines for the progress output.
std::vector<std::string> describeAllocation(const TermAllocation& allocation);

}  // namespace vktg
