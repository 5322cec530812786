#include "vk/memory_arena.h"

#include "vk/memory_guard.h"
#include "vk/vk_check.h"
#include "vktg/error.h"

namespace vktg {

MemoryArena::MemoryArena(const VulkanContext& context, std::string name)
    : m_context(context), m_name(std::move(name)) {}

void MemoryArena::release() {
  if (m_memory) {
    releaseMemoryGuards(m_memory);
    vkFreeMemory(m_context.device(), m_memory, nullptr);  // unmaps implicitly
  }
  m_memory = VK_NULL_HANDLE;
  m_mapped = nullptr;
  m_capacity = 0;
}

void MemoryArena::bind(const std::vector<Buffer*>& buffers) {
  const VkDevice device = m_context.device();
  // Offsets in the block: each buffer at its own alignment after the one before (and its guard).
  const VkDeviceSize guard = memoryGuardsOn() ? kGuardBytes : 0;
  std::vector<VkDeviceSize> offsets;
  VkDeviceSize end = 0;
  uint32_t typeBits = ~0u;
  for (const Buffer* b : buffers) {
    if (b->m_boundMemory) throw Error("memory arena '" + m_name + "': buffer '" + b->name() + "' is bound already");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b->handle(), &req);
    const VkDeviceSize offset = (end + req.alignment - 1) / req.alignment * req.alignment;
    offsets.push_back(offset);
    end = offset + req.size + guard;
    typeBits &= req.memoryTypeBits;
  }
  if (typeBits == 0) throw Error("memory arena '" + m_name + "': its buffers share no memory type");
  const VkMemoryPropertyFlags flags = memoryFlagsFor(m_context, typeBits, MemoryKind::Device);
  const uint32_t typeIndex = m_context.findMemoryType(typeBits, flags);
  if (end > m_capacity || (m_memory && typeIndex != m_typeIndex)) {
    release();
    m_memory = allocateDeviceMemory(m_context, end, typeIndex, m_name);
    m_capacity = end;
    m_typeIndex = typeIndex;
    ++m_allocations;
    if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
      VKTG_VK_CHECK(vkMapMemory(device, m_memory, 0, VK_WHOLE_SIZE, 0, &m_mapped));
      m_coherent = m_context.hasMemoryType(1u << typeIndex, VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
      m_readDirectly = m_context.hasMemoryType(1u << typeIndex, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    }
  }
  if (guard && m_mapped && m_readDirectly) {
    releaseMemoryGuards(m_memory);
    for (size_t k = 0; k < buffers.size(); ++k) {
      const VkDeviceSize from = offsets[k] + buffers[k]->size(), to = k + 1 < buffers.size() ? offsets[k + 1] : end;
      guardMemory(m_memory, static_cast<char*>(m_mapped) + from, to - from, buffers[k]->name());
    }
  }
  size_t i = 0;
  for (Buffer* b : buffers) {
    VKTG_VK_CHECK(vkBindBufferMemory(device, b->handle(), m_memory, offsets[i]));
    b->m_boundMemory = m_memory;
    b->m_mapped = m_mapped ? static_cast<char*>(m_mapped) + offsets[i] : nullptr;
    b->m_coherent = m_coherent;
    b->m_readDirectly = m_readDirectly;
    ++i;
  }
}

}  // namespace vktg
