// Fills gpu::FrameUniforms: the camera, scene counts and chunk layout (sceneFrameUniforms), to
// which the renderer adds the gate and path settings of its plan.
#pragma once
#include "host/gpu_scene.h"
#include "vktg/gpu/shared.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {

gpu::FrameUniforms sceneFrameUniforms(const Scene& scene, const PreparedScene& prepared, const GpuScene& gpuScene);

// Scene diagonal and the ray offset used to leave a surface (relative to the scene's scale).
float sceneDiagonal(const PreparedScene& prepared);

}  // namespace vktg
