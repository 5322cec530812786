#include "render/wavefront.h"

#include <algorithm>

#include "vktg/error.h"
#include "vktg/gpu/shared.h"

namespace vktg {

uint64_t wavefrontBytesPerPath(uint32_t layers, uint32_t lanes, const ExtraPathState& extra) {
  return sizeof(gpu::PathState) + sizeof(gpu::HitRecord) + 4 * sizeof(uint32_t) +
         gpu::kShadowRaysPerPath * sizeof(gpu::ShadowRay) + uint64_t(layers) * (1 + lanes) * sizeof(float) +
         uint64_t(lanes) * (sizeof(gpu::PathDerivative) + gpu::kShadowRaysPerPath * 2 * sizeof(float)) + extra.bytes;
}

uint32_t batchSizeFor(uint64_t budgetBytes, uint32_t layers, uint32_t lanes, uint64_t maxBufferRange,
                      uint64_t maxPaths, uint32_t maxGroups, const ExtraPathState& extra) {
  uint64_t batch = budgetBytes / wavefrontBytesPerPath(layers, lanes, extra);
  // Every per-path buffer must be bindable as one storage buffer.
  uint64_t largestPerPath = std::max<uint64_t>({gpu::kShadowRaysPerPath * sizeof(gpu::ShadowRay),
                                                uint64_t(layers) * (1 + lanes) * 4,
                                                uint64_t(lanes) * sizeof(gpu::PathDerivative), extra.largestBuffer});
  batch = std::min(batch, maxBufferRange / largestPerPath);
  batch = std::min<uint64_t>(batch, uint64_t(maxGroups) * gpu::kWorkgroupSize / (std::max(layers, 1u) * (1 + lanes)));
  batch = std::min<uint64_t>(batch, 1u << 22);
  if (batch < gpu::kWorkgroupSize)
    throw Error("--mem: the memory budget holds fewer than " + std::to_string(gpu::kWorkgroupSize) +
                " paths of wavefront state (" + std::to_string(wavefrontBytesPerPath(layers, lanes, extra)) +
                " bytes each); raise it");
  uint64_t rounded = std::max<uint64_t>(gpu::kWorkgroupSize, (std::min(batch, std::max<uint64_t>(maxPaths, 1)) +
                                                             gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize * gpu::kWorkgroupSize);
  return uint32_t(std::min(rounded, batch / gpu::kWorkgroupSize * gpu::kWorkgroupSize));
}

WavefrontBuffers::WavefrontBuffers(const VulkanContext& context, uint32_t batchSize, uint32_t layers, uint32_t lanes)
    : paths(context, uint64_t(batchSize) * sizeof(gpu::PathState), MemoryKind::Device, "wavefront.paths", Binding::Arena),
      hits(context, uint64_t(batchSize) * sizeof(gpu::HitRecord), MemoryKind::Device, "wavefront.hits", Binding::Arena),
      rayQueues(context, 4ull * batchSize * sizeof(uint32_t), MemoryKind::Device, "wavefront.rayQueues",
                Binding::Arena),
      shadowQueue(context, uint64_t(gpu::kShadowRaysPerPath) * batchSize * sizeof(gpu::ShadowRay), MemoryKind::Device,
                  "wavefront.shadowQueue", Binding::Arena),
      counters(context, gpu::kCounterCount * sizeof(uint32_t), MemoryKind::Device, "wavefront.counters",
               Binding::Arena),
      dispatchArgs(context, 3 * gpu::kArgsCount * sizeof(uint32_t), MemoryKind::Device, "wavefront.dispatchArgs",
                   Binding::Arena),
      pathAccum(context, uint64_t(batchSize) * layers * (1 + lanes) * sizeof(float), MemoryKind::Device,
                "wavefront.pathAccum", Binding::Arena),
      pathDerivs(context, std::max<uint64_t>(16, uint64_t(batchSize) * lanes * sizeof(gpu::PathDerivative)),
                 MemoryKind::Device, "wavefront.pathDerivs", Binding::Arena),
      shadowDerivs(context, std::max<uint64_t>(16, uint64_t(gpu::kShadowRaysPerPath) * batchSize * lanes * 2 * sizeof(float)),
                   MemoryKind::Device, "wavefront.shadowDerivs", Binding::Arena) {}

namespace {

// Every buffer of `w` (const or not), in one place for all() and bytes().
template <class Wave>
auto buffersOf(Wave& w) {
  return std::vector{&w.paths, &w.hits, &w.rayQueues, &w.shadowQueue, &w.counters, &w.dispatchArgs, &w.pathAccum,
                     &w.pathDerivs, &w.shadowDerivs};
}

}  // namespace

std::vector<Buffer*> WavefrontBuffers::all() { return buffersOf(*this); }

uint64_t WavefrontBuffers::bytes() const {
  uint64_t total = 0;
  for (const Buffer* b : buffersOf(*this)) total += b->size();
  return total;
}

}  // namespace vktg
