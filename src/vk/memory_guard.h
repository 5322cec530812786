// Guards after device buffers (VKTG_GUARD_MEMORY=1; the tests turn it on): each device allocation
// the host maps cached gets kGuardBytes after every buffer in it, filled with a pattern and checked
// after every submission. On lavapipe device memory is the host's heap, where a pass writing past a
// buffer's end corrupts whatever lies there and surfaces, if at all, as a crash far away; with the
// guards the submission that wrote it fails, naming the buffer. Memory the host cannot map has none,
// nor has a GPU's memory mapped uncached, which the host would read back at tens of MB/s after
// every submission.
#pragma once
#include <cstddef>
#include <string>

#include <vulkan/vulkan.h>

namespace vktg {

inline constexpr VkDeviceSize kGuardBytes = 4096;

// Whether allocations get guards (read once per process).
bool memoryGuardsOn();
// Fills `bytes` at `start` (mapped, inside `memory`) with the pattern and watches them.
void guardMemory(VkDeviceMemory memory, void* start, size_t bytes, const std::string& bufferName);
// Stops watching every guard inside `memory` (before it is freed or rebound).
void releaseMemoryGuards(VkDeviceMemory memory);
// Throws Error naming the first buffer whose guard changed.
void checkMemoryGuards();

}  // namespace vktg
