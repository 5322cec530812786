#include "render/frame_uniforms.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace vktg {
namespace {
constexpr double kSqrtTwoPi = 2.50662827463100050242;
}  // namespace


float sceneDiagonal(const PreparedScene& prepared) {
  return std::max(glm::length(prepared.boundsMax - prepared.boundsMin), 1e-6f);
}

float surfaceOffset(const PreparedScene& prepared) {
  // Offsets must exceed float rounding at the scene's coordinates (ulp ~ 6e-8 of the magnitude).
  const float magnitude =
      std::max({glm::length(prepared.boundsMin), glm::length(prepared.boundsMax), sceneDiagonal(prepared)});
  return 2e-5f * magnitude;
}

CameraBasis cameraBasis(const Camera& camera) {
  const glm::vec3 forward = glm::normalize(camera.lookAt - camera.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tanHalf = std::tan(glm::radians(camera.fovY) * 0.5f);
  const float aspect = float(camera.width) / float(camera.height);
  return {forward, right * tanHalf * aspect, up * tanHalf};
}

gpu::FrameUniforms sceneFrameUniforms(const Camera& cam, const RenderSettings& settings, const PreparedScene& prepared,
                                      const GpuScene& gpuScene) {
  gpu::FrameUniforms f{};
  f.cameraPosition = glm::vec4(cam.position, 0.0f);
  if (cam.type == CameraType::Perspective) {
    const CameraBasis basis = cameraBasis(cam);
    f.cameraForward = glm::vec4(basis.forward, 0.0f);
    f.cameraRight = glm::vec4(basis.right, 0.0f);
    f.cameraUp = glm::vec4(basis.up, 0.0f);
    f.image = glm::uvec4(cam.width, cam.height, settings.spp, settings.seed);
  } else {
    f.cameraForward = glm::vec4(glm::normalize(cam.normal), 0.0f);
    f.image = glm::uvec4(1, 1, settings.spp, settings.seed);
  }
  f.sceneCounts = glm::uvec4(uint32_t(prepared.triangles.size()), uint32_t(prepared.lights.size()),
                             uint32_t(prepared.shapes.size()), uint32_t(cam.type));
  float diagonal = sceneDiagonal(prepared);
  f.sceneInfo = glm::vec4(surfaceOffset(prepared), diagonal, prepared.totalLightPower,
                         std::bit_cast<float>(uint32_t(prepared.vertices.size())));
  f.chunkShift = glm::uvec4(gpuScene.triangles.shift, gpuScene.bvhNodes.shift, 31, 0);
  f.pathInfo = glm::uvec4(settings.rouletteDepth, 0, 1, 0);
  f.gateInfo = glm::uvec4(0, 1, 0, settings.maxDepth);
  // One view; point lights follow the area lights in lights[] (prepareLights).
  const auto pointLights = std::count_if(prepared.lights.begin(), prepared.lights.end(),
                                         [](const gpu::GpuLight& l) { return l.type == gpu::kLightPoint; });
  f.viewInfo = glm::uvec4(1, f.image.y, 0, uint32_t(prepared.lights.size() - size_t(pointLights)));
  return f;
}

void setGateUniforms(gpu::FrameUniforms& f, const Gate& gate, bool gateCutoff) {
  switch (gate.type) {
    case GateType::Bins: f.gate = glm::vec4(float(gate.binStart), float(gate.binWidth), 0, 0); break;
    default: f.gate = glm::vec4(float(gate.mu), float(gate.sigma), float(gate.a), float(gate.b)); break;
  }
  float supportMax = gateCutoff ? float(gate.supportMax()) : std::numeric_limits<float>::infinity();
  float normaliser = (gate.type == GateType::Gaussian && gate.normalize) ? float(1.0 / (gate.sigma * kSqrtTwoPi)) : 1.0f;
  float trueMax = std::isfinite(gate.supportMax()) ? float(gate.supportMax()) : 0.0f;
  f.gateSupport = glm::vec4(float(gate.supportMin()), supportMax, trueMax, normaliser);
  f.gateInfo.x = uint32_t(gate.type);
  f.gateInfo.y = gate.layers();
}

}  // namespace vktg
