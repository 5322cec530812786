#include "vk/vk_resources.h"

#include <algorithm>
#include <cstring>

#include "vk/forced_choice.h"
#include "vk/memory_guard.h"
#include "vk/vk_check.h"
#include "vktg/error.h"

namespace vktg {

VkMemoryPropertyFlags memoryFlagsFor(const VulkanContext& context, uint32_t memoryTypeBits, MemoryKind kind) {
  constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  if (kind == MemoryKind::Device) {
    constexpr VkMemoryPropertyFlags kLocal = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    // VKTG_DEVICE_MEMORY=staged leaves device memory unmapped, as on a discrete GPU without a
    // host-visible heap, so that every device (lavapipe in tests) can run the staging copies.
    const bool mapped = forcedChoice("VKTG_DEVICE_MEMORY", "mapped", "staged").value_or(true);
    return mapped && context.hasMemoryType(memoryTypeBits, kLocal | kHost) ? kLocal | kHost : kLocal;
  }
  constexpr VkMemoryPropertyFlags kCached = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  return context.hasMemoryType(memoryTypeBits, kCached) ? kCached : kHost;
}

VkDeviceMemory allocateDeviceMemory(const VulkanContext& context, VkDeviceSize size, uint32_t typeIndex,
                                    const std::string& name) {
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = size;
  alloc.memoryTypeIndex = typeIndex;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkResult result = context.allocateMemory(alloc, &memory);
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
    throw DeviceFault(context.report().name + ": out of " +
                      (result == VK_ERROR_OUT_OF_DEVICE_MEMORY ? "device" : "host") + " memory allocating '" + name +
                      "' (" + std::to_string((size + (1u << 20) - 1) >> 20) +
                      " MiB); lower --mem, the resolution, the bins or the parameters per block");
  VKTG_VK_CHECK(result);
  return memory;
}

Buffer::Buffer(const VulkanContext& context, VkDeviceSize size, MemoryKind kind, const std::string& name,
               Binding binding)
    : m_device(context.device()), m_size(size), m_name(name) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size > 0 ? size : 16;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VKTG_VK_CHECK(vkCreateBuffer(m_device, &info, nullptr, &m_buffer));
  context.setObjectName(VK_OBJECT_TYPE_BUFFER, uint64_t(m_buffer), name);
  if (binding == Binding::Arena) return;  // MemoryArena::bind gives it memory
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(m_device, m_buffer, &req);
  const VkMemoryPropertyFlags flags = memoryFlagsFor(context, req.memoryTypeBits, kind);
  const uint32_t typeIndex = context.findMemoryType(req.memoryTypeBits, flags);
  const bool cached = (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) &&
                      context.hasMemoryType(1u << typeIndex, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  const VkDeviceSize guard = memoryGuardsOn() && cached ? kGuardBytes : 0;
  try {
    m_memory = allocateDeviceMemory(context, req.size + guard, typeIndex, name);
  } catch (...) {
    reset();
    throw;
  }
  VKTG_VK_CHECK(vkBindBufferMemory(m_device, m_buffer, m_memory, 0));
  m_boundMemory = m_memory;
  if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
    VKTG_VK_CHECK(vkMapMemory(m_device, m_memory, 0, VK_WHOLE_SIZE, 0, &m_mapped));
    m_coherent = context.hasMemoryType(1u << typeIndex, VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    // A readback buffer is the staging buffer itself: read directly even where no cached type exists.
    m_readDirectly = kind == MemoryKind::Readback || cached;
    if (guard) guardMemory(m_memory, static_cast<char*>(m_mapped) + size, req.size + guard - size, name);
  }
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    reset();
    m_device = other.m_device;
    m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
    m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
    m_size = std::exchange(other.m_size, 0);
    m_mapped = std::exchange(other.m_mapped, nullptr);
    m_coherent = other.m_coherent;
    m_readDirectly = other.m_readDirectly;
    m_boundMemory = std::exchange(other.m_boundMemory, VK_NULL_HANDLE);
    m_name = std::move(other.m_name);
  }
  return *this;
}

void Buffer::reset() {
  if (m_buffer) vkDestroyBuffer(m_device, m_buffer, nullptr);
  if (m_memory) {
    releaseMemoryGuards(m_memory);
    vkFreeMemory(m_device, m_memory, nullptr);  // unmaps implicitly
  }
  m_buffer = VK_NULL_HANDLE;
  m_memory = VK_NULL_HANDLE;
  m_mapped = nullptr;
  m_boundMemory = VK_NULL_HANDLE;
}

void Buffer::upload(const VulkanContext& context, const void* data, size_t bytes, size_t offset) {
  if (bytes == 0) return;
  if (m_mapped) {
    std::memcpy(static_cast<char*>(m_mapped) + offset, data, bytes);
    if (!m_coherent) {
      VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, m_boundMemory, 0, VK_WHOLE_SIZE};
      VKTG_VK_CHECK(vkFlushMappedMemoryRanges(m_device, 1, &range));
    }
    return;
  }
  Buffer staging(context, bytes, MemoryKind::Readback, m_name + ".staging");
  staging.upload(context, data, bytes);
  CommandBuffer cmd(context, "upload " + m_name);
  cmd.begin();
  VkBufferCopy region{0, offset, bytes};
  vkCmdCopyBuffer(cmd.get(), staging.handle(), m_buffer, 1, &region);
  computeBarrier(cmd.get());  // for the passes of later submissions
  cmd.end();
  context.submitAndWait(cmd.get());
}

void Buffer::download(const VulkanContext& context, void* data, size_t bytes, size_t offset, Buffer* staging) const {
  if (bytes == 0) return;
  // A few uncached reads (a render's counters) cost less than a copy's submission and wait.
  constexpr size_t kUncachedReadBytes = 4096;
  if (m_mapped && (m_readDirectly || bytes <= kUncachedReadBytes)) {
    if (!m_coherent) {
      VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, m_boundMemory, 0, VK_WHOLE_SIZE};
      VKTG_VK_CHECK(vkInvalidateMappedMemoryRanges(m_device, 1, &range));
    }
    std::memcpy(data, static_cast<const char*>(m_mapped) + offset, bytes);
    return;
  }
  Buffer fresh;
  if (!staging || staging->size() < bytes) {
    fresh = Buffer(context, bytes, MemoryKind::Readback, m_name + ".readback");
    staging = &fresh;
  }
  CommandBuffer cmd(context, "download " + m_name);
  cmd.begin();
  computeBarrier(cmd.get());  // what the passes of earlier submissions wrote
  VkBufferCopy region{offset, 0, bytes};
  vkCmdCopyBuffer(cmd.get(), m_buffer, staging->handle(), 1, &region);
  hostReadBarrier(cmd.get());
  cmd.end();
  context.submitAndWait(cmd.get());
  staging->download(context, data, bytes);
}

CommandBuffer::CommandBuffer(const VulkanContext& context, const std::string& name)
    : m_device(context.device()), m_pool(context.commandPool()) {
  VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  info.commandPool = m_pool;
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  VKTG_VK_CHECK(vkAllocateCommandBuffers(m_device, &info, &m_cmd));
  context.setObjectName(VK_OBJECT_TYPE_COMMAND_BUFFER, uint64_t(m_cmd), name);
}

CommandBuffer::~CommandBuffer() {
  if (m_cmd) vkFreeCommandBuffers(m_device, m_pool, 1, &m_cmd);
}

void CommandBuffer::begin() {
  VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VKTG_VK_CHECK(vkResetCommandBuffer(m_cmd, 0));
  VKTG_VK_CHECK(vkBeginCommandBuffer(m_cmd, &info));
}

void CommandBuffer::end() { VKTG_VK_CHECK(vkEndCommandBuffer(m_cmd)); }

void computeBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                          VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                           VK_PIPELINE_STAGE_TRANSFER_BIT,
                       0, 1, &barrier, 0, nullptr, 0, nullptr);
}

Buffer& grownBuffer(const VulkanContext& context, Buffer& buffer, VkDeviceSize bytes, MemoryKind kind,
                    const std::string& name) {
  if (!buffer || buffer.size() < bytes) buffer = Buffer(context, bytes, kind, name);
  return buffer;
}

void recordUpdate(VkCommandBuffer cmd, const Buffer& buffer, const void* data, size_t bytes, size_t offset) {
  constexpr size_t kMaxUpdateBytes = 65536;
  if (bytes % 4 != 0 || offset % 4 != 0 || offset + bytes > buffer.size())
    throw Error("internal: a recorded update of " + buffer.name() + " must be whole words inside it");
  for (size_t at = 0; at < bytes; at += kMaxUpdateBytes)
    vkCmdUpdateBuffer(cmd, buffer.handle(), offset + at, std::min(kMaxUpdateBytes, bytes - at),
                      static_cast<const char*>(data) + at);
}

void hostReadBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

}  // namespace vktg
