// The Vulkan instance, chosen device, compute queue and the debug machinery (validation messages,
// object names, labels). Headless: no surface or window-system extension is ever requested.
#pragma once
#include <atomic>
#include <cstdlib>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vk/fault_injection.h"
#include "vktg/error.h"
#include "vktg/gpu/shared.h"

namespace vktg {

struct ContextOptions {
  // "" = best available; "gpu" = best usable non-CPU device; a number = index in `vktg info`;
  // else a name substring
  std::string device;
  bool validation = false;  // Khronos validation layer; every message is recorded (and fails tests)
};

// Options from the environment: VKTG_DEVICE (the default for --device) and VKTG_VALIDATION=1.
ContextOptions contextOptionsFromEnvironment();

// What `vktg info` prints about one physical device.
struct DeviceReport {
  uint32_t index = 0;
  std::string name;
  std::string type;        // discrete, integrated, virtual, cpu, other
  std::string driver;      // driver name and info
  std::string apiVersion;
  bool usable = false;
  std::string missing;     // why not usable
  uint64_t maxStorageBufferRange = 0;
  uint32_t maxComputeWorkGroupCount = 0;
  uint32_t maxComputeWorkGroupInvocations = 0;
  uint32_t maxPushConstantsSize = 0;
  uint32_t maxPerStageStorageBuffers = 0;
  uint64_t deviceLocalBytes = 0;
  float timestampPeriodNs = 0;
  bool floatAtomicAdd = false;
  bool subgroupBallotArithmetic = false;  // in compute shaders
  bool int64Atomics = false;
};

// The device failed underneath a run: memory exhausted, device lost, a submission that never
// finished. The message says what happened and what to try.
class DeviceFault : public Error {
 public:
  using Error::Error;
};

// How long one submission may run before it counts as stuck (batches are sized to take seconds).
inline constexpr uint64_t kFenceTimeoutNs = 600ull * 1000 * 1000 * 1000;

// Whether command-buffer labels (for capture tools) are recorded with the validation layer at
// `layerVersion` (0: no validation). Layers before 1.3.243 erase a freed command buffer's labels on
// their queue thread without the lock that recording a label takes (Vulkan-ValidationLayers issue
// 5172, fixed in February 2023; Debian 12 ships 1.3.239): the two threads then corrupt the heap,
// which valgrind showed as a write into a freed block in vkCmdBeginDebugUtilsLabelEXT during a
// whole optimisation, the runs that lost a test to heap corruption on lavapipe.
bool labelsAreSafe(uint32_t layerVersion);

// Whether a VulkanContext went with validation messages nobody had taken: those the layer reports
// while the device is destroyed (objects never destroyed) come after every check a command makes,
// so the destructor prints them ("vktg: validation at exit: ...") and main() fails the run with this.
bool validationFailedAtExit();

class VulkanContext {
 public:
  explicit VulkanContext(const ContextOptions& options);
  ~VulkanContext();  // see validationFailedAtExit
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return m_instance; }
  VkPhysicalDevice physicalDevice() const { return m_physical; }
  VkDevice device() const { return m_device; }
  VkQueue queue() const { return m_queue; }
  uint32_t queueFamily() const { return m_queueFamily; }
  VkCommandPool commandPool() const { return m_commandPool; }
  const VkPhysicalDeviceProperties& properties() const { return m_properties; }
  const DeviceReport& report() const { return m_report; }
  bool isCpuDevice() const { return m_properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }

  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;
  bool hasMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;

  void setObjectName(VkObjectType type, uint64_t handle, const std::string& name) const;
  void beginLabel(VkCommandBuffer cmd, const char* name) const;
  void endLabel(VkCommandBuffer cmd) const;

  // Submits and blocks until the GPU is done; a lost device or a submission still running after
  // kFenceTimeoutNs throws DeviceFault.
  void submitAndWait(VkCommandBuffer cmd) const;
  // vkAllocateMemory (with VKTG_INJECT_FAULT's allocation faults and leak).
  VkResult allocateMemory(const VkMemoryAllocateInfo& info, VkDeviceMemory* memory) const;
  // Round trips and allocations so far: each costs a GPU's host tens of microseconds or more, which
  // small renders feel (tests count them per render).
  uint64_t submissionCount() const { return m_submissions.load(); }
  uint64_t allocationCount() const { return m_allocations.load(); }

  // Validation messages recorded so far (warnings and errors); tests fail on any.
  std::vector<std::string> takeValidationMessages();
  // Destroys the device and instance now and returns the messages recorded meanwhile: the
  // validation layer reports objects never destroyed when the device goes, which no earlier check
  // can see. The context is unusable afterwards.
  std::vector<std::string> destroyAndTakeValidationMessages();
  uint64_t validationMessageCount() const { return m_messageCount.load(); }

  static std::vector<DeviceReport> listDevices();

  // The object stored under `key`, made by `make` the first time: objects that live as long as the
  // device and serve everything created on it (the compiled pipelines every renderer of this context
  // reuses: on lavapipe a renderer's pipelines take seconds to make). Destroyed before the device.
  template <class T>
  std::shared_ptr<T> shared(const std::string& key, const std::function<std::shared_ptr<T>()>& make) {
    std::lock_guard lock(m_sharedMutex);
    std::shared_ptr<void>& slot = m_shared[key];
    if (!slot) slot = make();
    return std::static_pointer_cast<T>(slot);
  }

 private:
  void release();  // destroys whatever was created (also on a failed construction)
  static VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                       void* user);
  VkInstance m_instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
  VkPhysicalDevice m_physical = VK_NULL_HANDLE;
  VkDevice m_device = VK_NULL_HANDLE;
  VkQueue m_queue = VK_NULL_HANDLE;
  uint32_t m_queueFamily = 0;
  VkCommandPool m_commandPool = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties m_properties{};
  VkPhysicalDeviceMemoryProperties m_memory{};
  DeviceReport m_report;
  PFN_vkSetDebugUtilsObjectNameEXT m_setName = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT m_beginLabel = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT m_endLabel = nullptr;
  mutable FaultInjection m_faults{std::getenv("VKTG_INJECT_FAULT")};
  // A submission never finished: the device may still be using everything, so it is not waited
  // for or destroyed (the process ends with it).
  mutable bool m_stuck = false;
  std::mutex m_sharedMutex;
  std::map<std::string, std::shared_ptr<void>> m_shared;
  std::mutex m_messageMutex;
  std::vector<std::string> m_messages;
  std::atomic<uint64_t> m_messageCount{0};
  mutable std::atomic<uint64_t> m_submissions{0}, m_allocations{0};
};

}  // namespace vktg
