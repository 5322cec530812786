// One block of device memory that the wavefront buffers of successive renders share. A renderer
// keeps its per-render buffers (path states, queues, tape) only while consecutive renders need the
// same ones; an optimisation alternates a render with the adjoint passes of its gradient, which
// need others, so each render used to free them and allocate new ones. Fresh memory costs: on
// lavapipe every page faults and is zeroed again (a 91 x 91, 8-spp render of `bench optimize` took
// 36 ms, 22 ms with its buffers kept), on a GPU each allocation is a driver call that maps and
// clears pages. The arena keeps one block, as large as the largest set of buffers so far, and binds
// each new set into it; it only grows, so it holds no more than the largest render needs at once.
#pragma once
#include <string>
#include <vector>

#include "vk/vk_resources.h"

namespace vktg {

class MemoryArena {
 public:
  MemoryArena(const VulkanContext& context, std::string name);
  ~MemoryArena() { release(); }
  MemoryArena(const MemoryArena&) = delete;
  MemoryArena& operator=(const MemoryArena&) = delete;

  // Binds the buffers (made with Binding::Arena and MemoryKind::Device) one after another from the
  // block's start, growing the block first where they do not fit. Buffers bound earlier alias the
  // same memory: they must be destroyed before, or at least never used after, this call.
  void bind(const std::vector<Buffer*>& buffers);

  VkDeviceSize capacity() const { return m_capacity; }
  // How many times the block was allocated (grown); for tests.
  uint32_t allocations() const { return m_allocations; }

 private:
  void release();

  const VulkanContext& m_context;
  std::string m_name;
  VkDeviceMemory m_memory = VK_NULL_HANDLE;
  VkDeviceSize m_capacity = 0;
  uint32_t m_typeIndex = 0;
  void* m_mapped = nullptr;
  bool m_coherent = true;
  bool m_readDirectly = false;
  uint32_t m_allocations = 0;
};

}  // namespace vktg
