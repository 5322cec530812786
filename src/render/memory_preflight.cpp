#include "render/memory_preflight.h"

#include <algorithm>

#include "vktg/error.h"
#include "vktg/gpu/shared.h"

namespace vktg {
namespace {

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

std::string breakdown(const RenderMemory& need) {
  return "film " + mib(need.film) + " for " + need.filmShape + ", scene " + mib(need.scene) + ", smallest batch " +
         mib(need.smallestBatch);
}

}  // namespace

RenderMemory filmAndBatchNeed(uint32_t width, uint32_t height, uint32_t layers, uint32_t channels, uint32_t lanes,
                              const ExtraPathState& extra) {
  RenderMemory need;
  need.film = uint64_t(width) * height * layers * channels * gpu::kFilmFloatsPerElement * sizeof(float);
  need.smallestBatch = wavefrontBytesPerPath(layers, lanes, extra) * gpu::kWorkgroupSize;
  need.filmShape = std::to_string(width) + " x " + std::to_string(height) + " pixels x " + std::to_string(layers) +
                   " layers x " + std::to_string(channels) + " channels";
  return need;
}

uint64_t defaultMemoryBudget(const VulkanContext& context) {
  constexpr uint64_t kCpuBudget = 512ull << 20, kLargestGpuBudget = 4096ull << 20;
  if (context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) return kCpuBudget;
  return std::clamp(context.report().deviceLocalBytes / 4, kCpuBudget, kLargestGpuBudget);
}

uint64_t checkRenderMemory(const VulkanContext& context, const RenderMemory& need, uint64_t budget) {
  if (budget == 0) budget = defaultMemoryBudget(context);
  const uint64_t device = context.report().deviceLocalBytes;
  if (device > 0 && need.total() > device)
    throw Error("render: needs at least " + mib(need.total()) + " of device memory (" + breakdown(need) + ") but " +
                context.report().name + " has " + mib(device) +
                "; lower the resolution, the number of bins or the parameters per block");
  // The budget is what the render may choose to spend: film and wavefront state. The scene is the
  // input's own size, so it counts against the device only (a default budget must not refuse a
  // large mesh that the device holds).
  const uint64_t budgeted = need.film + need.smallestBatch;
  if (budgeted > budget)
    throw Error("--mem: " + mib(budget) + " cannot hold this render, which needs at least " + mib(budgeted) +
                " for its film and wavefront state (" + breakdown(need) + "; the scene is not counted); raise it");
  return device > 0 ? std::min(budget, device - need.scene) : budget;
}

}  // namespace vktg
