// Compile-time checks that the host's view of the shared GPU structs matches std430 in GLSL.
#include <cstddef>

#include "vktg/gpu/shared.h"

namespace vktg::gpu {
static_assert(sizeof(GpuTriangle) == 48);
static_assert(sizeof(GpuBvhNode) == 64);
static_assert(sizeof(GpuWideBvhNode) == 128);
static_assert(sizeof(GpuShape) == 16);
static_assert(sizeof(GpuParameterOp) == 32);
static_assert(sizeof(GpuMaterial) == 16);
static_assert(sizeof(GpuLight) == 32 && offsetof(GpuLight, type) == 16);
static_assert(sizeof(FrameUniforms) == 17 * 16 && offsetof(FrameUniforms, edgeInfo) == 12 * 16 &&
              offsetof(FrameUniforms, adjointScale) == 15 * 16);
static_assert(sizeof(GpuEdge) == 64);
static_assert(sizeof(PathState) == 96 && offsetof(PathState, previous) == 80);
static_assert(sizeof(GpuLane) == 32 && sizeof(PathDerivative) == 32);
static_assert(sizeof(HitRecord) == 16);
static_assert(sizeof(ShadowRay) == 64 && offsetof(ShadowRay, info) == 48);
static_assert(sizeof(ShadowAdjoint) == 32 && sizeof(TapeVertex) == 32 && sizeof(EdgeRecord) == 64);
}  // namespace vktg::gpu
namespace vktg::gpu {
static_assert(sizeof(PassPush) == 16);
}  // namespace vktg::gpu

#include "vktg/parameters.h"
namespace vktg::gpu {
static_assert(kParameterTranslate == uint(ParameterKind::Translate) && kParameterRotate == uint(ParameterKind::Rotate) &&
              kParameterDisplace == uint(ParameterKind::Displace));
}  // namespace vktg::gpu
