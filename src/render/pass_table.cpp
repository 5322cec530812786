#include "render/pass_table.h"

#include "vktg/error.h"
#include "vktg/gpu/shared.h"

namespace vktg {
namespace {

// The derivative variants of the per-pixel passes carry the lanes (_d) or the adjoint (_adj); the
// primal passes are shared by every term that has no derivative work in them.
constexpr std::array<const char*, kRenderModes> kGenerateCameraRays = {"generate_camera_rays", "generate_camera_rays_d",
                                                                       "generate_camera_rays_adj"};
constexpr std::array<const char*, kRenderModes> kShade = {"shade", "shade_d", "shade_adj"};
constexpr std::array<const char*, kRenderModes> kShadow = {"trace_shadow_rays", "trace_shadow_rays_d",
                                                           "trace_shadow_rays_adj"};
// Per-pixel paths end a batch in the film (forward) or in the adjoint's last step, which also
// accumulates where an adjoint render returns its image.
constexpr std::array<const char*, kRenderModes> kPerPixelFinish = {"accumulate", "accumulate", "backprop_paths"};

const TermPasses kTable[] = {
    {Term::Interior, true, true, true, false, false, true, false, false, gpu::kTermInterior, false, "--spp",
     kGenerateCameraRays, kShade, kShadow, kPerPixelFinish},
    // The light sides of edge samples are plain paths: sample_edges records the boundary segment
    // and scatter_edges (adjoint) or accumulate_splats (forward) turns the paths into derivatives.
    {Term::Edge, false, true, true, false, true, true, true, true, gpu::kTermInterior, false, "--spp-edge",
     {"", "sample_edges", "sample_edges"},
     {"", "shade", "shade"},
     {"", "trace_shadow_rays", "trace_shadow_rays"},
     {"", "accumulate_splats", "scatter_edges"}},
    {Term::PathLength, false, true, true, true, false, true, false, false, gpu::kTermPathLength, false, "--spp-boundary",
     kGenerateCameraRays, kShade, kShadow, kPerPixelFinish},
    // connect_camera_boundary queues complete connections: their shadow rays are the whole render;
    // an adjoint one scatters as it traces them.
    {Term::PathLengthFromCamera, false, true, true, true, true, false, false, false, gpu::kTermPathLength, true,
     "--spp-boundary-camera",
     {"", "connect_camera_boundary", "connect_camera_boundary_adj"},
     {"", "", ""},
     {"", "trace_shadow_rays_d", "trace_shadow_rays_adj"},
     {"", "accumulate_splats", ""}},
    {Term::InteriorAndPathLength, false, false, true, true, false, true, false, false, gpu::kTermInteriorAndPathLength,
     false, "--spp", kGenerateCameraRays, kShade, kShadow, kPerPixelFinish},
};

}  // namespace

const char* renderModeName(RenderMode mode) {
  switch (mode) {
    case RenderMode::Primal: return "primal";
    case RenderMode::Forward: return "forward";
    case RenderMode::Adjoint: return "adjoint";
  }
  return "?";
}

bool TermPasses::has(RenderMode mode) const {
  return mode == RenderMode::Primal ? primal : mode == RenderMode::Forward ? forward : adjoint;
}

const TermPasses& termPasses(Term term) {
  for (const TermPasses& row : kTable)
    if (row.term == term) return row;
  throw Error("internal: no passes for term " + std::to_string(uint32_t(term)));
}

}  // namespace vktg
