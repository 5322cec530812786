// The device memory a render needs, checked before anything large is allocated, so a render
// that cannot fit fails at once with the budget it would need instead of mid-way with an
// allocation error.
#pragma once
#include <cstdint>
#include <string>

#include "vk/vk_context.h"
#include "render/wavefront.h"

namespace vktg {

struct RenderMemory {
  uint64_t film = 0;              // bytes of the film (all layers and channels)
  uint64_t scene = 0;             // bytes of the uploaded scene and edge list
  uint64_t smallestBatch = 0;     // bytes of wavefront state for one workgroup of paths
  std::string filmShape;          // "W x H pixels x L layers x C channels", for the message
  uint64_t total() const { return film + scene + smallestBatch; }
};

// The film (4 floats per element, see gpu/shared.h) and the smallest batch (one workgroup of
// paths with `extra` state each) of a width x height render with `layers` gate layers and
// `channels` channels; the scene is left for the caller to add.
RenderMemory filmAndBatchNeed(uint32_t width, uint32_t height, uint32_t layers, uint32_t channels, uint32_t lanes,
                              const ExtraPathState& extra = {});

// The budget a render sizes its batches from when none is given (RenderOptions::memoryBudget 0):
// 512 MiB on a CPU device; on a GPU a quarter of its device-local memory, at most 4 GiB and at least
// 512 MiB. Larger batches pay the per-batch dispatches fewer times: on an H200 a 1024 x 1024,
// 256-spp render of the default room traced 2.35e8 paths/s with 512 MiB and 3.41e8 with 4 GiB.
// A CPU device gains nothing from batches beyond its few cores' reach and keeps memory for the host.
uint64_t defaultMemoryBudget(const VulkanContext& context);

// Throws vktg::Error when the film and smallest batch of `need` exceed the memory budget (--mem; 0:
// defaultMemoryBudget), or all of it (scene too) the device's device-local memory, naming what it
// would take. Returns the budget to size the film and batches from: the smaller of the budget and
// what the device holds beside the scene.
uint64_t checkRenderMemory(const VulkanContext& context, const RenderMemory& need, uint64_t budget);

}  // namespace vktg
