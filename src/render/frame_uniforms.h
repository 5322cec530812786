// Fills gpu::FrameUniforms: the camera, scene counts and chunk layout (sceneFrameUniforms), to
// which the renderer adds the gate and path settings of its plan.
#pragma once
#include "render/gpu_scene.h"
#include "vktg/gpu/shared.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {

gpu::FrameUniforms sceneFrameUniforms(const Camera& camera, const RenderSettings& settings, const PreparedScene& prepared,
                                      const GpuScene& gpuScene);

// Gate numbers (gate, gateSupport, gateInfo.x/y). Without the cutoff, paths are not ended when
// their length passes the gate (same image, more work: the benchmark measures the saving).
void setGateUniforms(gpu::FrameUniforms& frame, const Gate& gate, bool gateCutoff);

// Scene diagonal and the ray offset used to leave a surface (relative to the scene's scale).
float sceneDiagonal(const PreparedScene& prepared);
float surfaceOffset(const PreparedScene& prepared);

// A perspective camera's frame: the ray through image point (u, v) in [0, 1]^2 (v downwards) has
// the direction forward + (2u - 1) right + (1 - 2v) up (right and up are scaled by the field of view).
struct CameraBasis {
  glm::vec3 forward, right, up;
};
CameraBasis cameraBasis(const Camera& camera);

}  // namespace vktg
