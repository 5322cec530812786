// Device buffers of one batch of paths (path state, hits, queues, shadow rays, counters, indirect
// arguments, per-path accumulators) and the batch size a memory budget allows.
#pragma once
#include <cstdint>
#include <vector>

#include "vk/vk_resources.h"

namespace vktg {

// Per-path state a render needs beyond the wavefront (adjoint tapes, edge records): its bytes per
// path in all, and the bytes per path of its largest single buffer.
struct ExtraPathState {
  uint64_t bytes = 0;
  uint64_t largestBuffer = 0;
};

// Bytes of wavefront state per path for `layers` gate layers.
uint64_t wavefrontBytesPerPath(uint32_t layers, uint32_t lanes, const ExtraPathState& extra = {});

// Largest batch within `budgetBytes` whose every buffer stays under `maxBufferRange`, clamped
// to [kWorkgroupSize, maxPaths]. Throws vktg::Error when not even one workgroup fits.
uint32_t batchSizeFor(uint64_t budgetBytes, uint32_t layers, uint32_t lanes, uint64_t maxBufferRange,
                      uint64_t maxPaths, uint32_t maxGroups, const ExtraPathState& extra = {});

struct WavefrontBuffers {
  // Unbound (Binding::Arena): the renderer binds them, with its other per-render buffers, into
  // its MemoryArena.
  WavefrontBuffers(const VulkanContext& context, uint32_t batchSize, uint32_t layers, uint32_t lanes);
  uint64_t bytes() const;
  std::vector<Buffer*> all();

  Buffer paths, hits, rayQueues, shadowQueue, counters, dispatchArgs, pathAccum;
  Buffer pathDerivs, shadowDerivs;  // derivative lanes (16 bytes when there are none)
};

}  // namespace vktg
