// Move-only RAII wrappers for the Vulkan objects vktg creates. Each carries a debug name (set on
// the object for validation messages and captures). Destruction order follows declaration order.
#pragma once
#include <cstddef>
#include <string>
#include <utility>

#include <vulkan/vulkan.h>

#include "vk/vk_context.h"

namespace vktg {

// A device-owned handle destroyed with `Destroy(device, handle, nullptr)`.
template <class Handle, auto Destroy>
class DeviceHandle {
 public:
  DeviceHandle() = default;
  DeviceHandle(VkDevice device, Handle handle) : m_device(device), m_handle(handle) {}
  ~DeviceHandle() { reset(); }
  DeviceHandle(DeviceHandle&& other) noexcept
      : m_device(other.m_device), m_handle(std::exchange(other.m_handle, VK_NULL_HANDLE)) {}
  DeviceHandle& operator=(DeviceHandle&& other) noexcept {
    if (this != &other) {
      reset();
      m_device = other.m_device;
      m_handle = std::exchange(other.m_handle, VK_NULL_HANDLE);
    }
    return *this;
  }
  DeviceHandle(const DeviceHandle&) = delete;
  DeviceHandle& operator=(const DeviceHandle&) = delete;

  Handle get() const { return m_handle; }
  explicit operator bool() const { return m_handle != VK_NULL_HANDLE; }
  void reset() {
    if (m_handle != VK_NULL_HANDLE) Destroy(m_device, m_handle, nullptr);
    m_handle = VK_NULL_HANDLE;
  }

 private:
  VkDevice m_device = VK_NULL_HANDLE;
  Handle m_handle = VK_NULL_HANDLE;
};

using ShaderModule = DeviceHandle<VkShaderModule, vkDestroyShaderModule>;
using Pipeline = DeviceHandle<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = DeviceHandle<VkPipelineLayout, vkDestroyPipelineLayout>;
using PipelineCache = DeviceHandle<VkPipelineCache, vkDestroyPipelineCache>;
using DescriptorSetLayout = DeviceHandle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = DeviceHandle<VkDescriptorPool, vkDestroyDescriptorPool>;
using QueryPool = DeviceHandle<VkQueryPool, vkDestroyQueryPool>;
using BufferView = DeviceHandle<VkBufferView, vkDestroyBufferView>;

enum class MemoryKind {
  Device,    // device-local; mapped too when the device offers host-visible device memory
  Readback,  // host-visible and cached, for copies back to the host
};

// Whether a buffer allocates its own memory or is bound later into a MemoryArena's block.
enum class Binding { OwnMemory, Arena };

// A buffer, with its own memory allocation or bound into a MemoryArena (host/memory_arena.h).
// Usable as storage, uniform, uniform texel, indirect and copy source/target.
class Buffer {
 public:
  Buffer() = default;
  Buffer(const VulkanContext& context, VkDeviceSize size, MemoryKind kind, const std::string& name,
         Binding binding = Binding::OwnMemory);
  ~Buffer() { reset(); }
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return m_buffer; }
  VkDeviceSize size() const { return m_size; }
  void* mapped() const { return m_mapped; }  // nullptr when not host-visible
  const std::string& name() const { return m_name; }
  explicit operator bool() const { return m_buffer != VK_NULL_HANDLE; }

  // Copies host data into the buffer (directly when mapped, else through a staging buffer).
  void upload(const VulkanContext& context, const void* data, size_t bytes, size_t offset = 0);
  // Copies `bytes` from `offset` back to the host: directly where the memory is mapped and cached
  // (or mapped and the read under 4 KiB), else through a staging buffer (`staging`, a Readback buffer of at least `bytes`, when given; a
  // fresh one otherwise). A GPU's host-visible device memory (resizable BAR) is mapped uncached, and
  // the host reads it at tens of MB/s: a copy by the device and a cached read are far faster.
  void download(const VulkanContext& context, void* data, size_t bytes, size_t offset = 0, Buffer* staging = nullptr) const;
  // Whether the host reads this buffer's memory directly (mapped and cached, or a readback buffer).
  bool hostReadable() const { return m_mapped && m_readDirectly; }
  void reset();

 private:
  friend class MemoryArena;
  VkDevice m_device = VK_NULL_HANDLE;
  VkBuffer m_buffer = VK_NULL_HANDLE;
  VkDeviceMemory m_memory = VK_NULL_HANDLE;  // owned; null for a buffer bound into an arena
  VkDeviceSize m_size = 0;
  void* m_mapped = nullptr;
  bool m_coherent = true;
  bool m_readDirectly = false;
  VkDeviceMemory m_boundMemory = VK_NULL_HANDLE;  // what the buffer is bound to (its own or an arena's); null: unbound
  std::string m_name;
};

// The memory properties a buffer of `kind` asks for on this device (`memoryTypeBits` from its
// requirements): device-local, mapped too where the device offers host-visible device memory
// (integrated GPUs, lavapipe, GPUs with a resizable BAR: uploads need no staging there, downloads
// only where that memory is cached); host-visible and cached for readback.
VkMemoryPropertyFlags memoryFlagsFor(const VulkanContext& context, uint32_t memoryTypeBits, MemoryKind kind);

// vkAllocateMemory through the context (fault injection), or a DeviceFault naming `name` and the
// size when the device or host is out of memory.
VkDeviceMemory allocateDeviceMemory(const VulkanContext& context, VkDeviceSize size, uint32_t typeIndex,
                                    const std::string& name);

// A primary command buffer from the context's pool, freed on destruction.
class CommandBuffer {
 public:
  CommandBuffer(const VulkanContext& context, const std::string& name);
  ~CommandBuffer();
  CommandBuffer(CommandBuffer&& other) noexcept
      : m_device(other.m_device), m_pool(other.m_pool), m_cmd(std::exchange(other.m_cmd, VK_NULL_HANDLE)) {}
  CommandBuffer(const CommandBuffer&) = delete;
  CommandBuffer& operator=(const CommandBuffer&) = delete;
  CommandBuffer& operator=(CommandBuffer&&) = delete;

  VkCommandBuffer get() const { return m_cmd; }
  void begin();
  void end();

 private:
  VkDevice m_device;
  VkCommandPool m_pool;
  VkCommandBuffer m_cmd = VK_NULL_HANDLE;
};

// `buffer`, made anew (contents lost) when it does not exist or holds fewer than `bytes`: for state
// kept between renders that only ever grows.
Buffer& grownBuffer(const VulkanContext& context, Buffer& buffer, VkDeviceSize bytes, MemoryKind kind,
                    const std::string& name);

// Full compute-to-compute (and indirect-argument, transfer) barrier between passes.
void computeBarrier(VkCommandBuffer cmd);
// Compute and transfer writes made visible to the host's reads after the submission's fence.
void hostReadBarrier(VkCommandBuffer cmd);
// Records a write of `bytes` of host data at `offset` of `buffer` into `cmd` (vkCmdUpdateBuffer, in
// pieces of at most 64 KiB; sizes and offsets multiples of 4): small per-render state without a
// staging buffer or a submission of its own.
void recordUpdate(VkCommandBuffer cmd, const Buffer& buffer, const void* data, size_t bytes, size_t offset);

}  // namespace vktg
