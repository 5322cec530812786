#include "vk/vk_context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "vk/memory_guard.h"
#include "vk/vk_check.h"
#include "vktg/error.h"

namespace vktg {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

// Lower is preferred: a discrete GPU first, lavapipe (cpu) last.
int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

bool hasExtension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> props(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, props.data());
  return std::any_of(props.begin(), props.end(), [&](const auto& p) { return std::strcmp(p.extensionName, name) == 0; });
}

// The spec version of instance layer `name`, 0 when it is not installed.
uint32_t instanceLayerVersion(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return std::max<uint32_t>(l.specVersion, 1);
  return 0;
}

bool instanceHasExtension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> props(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, props.data());
  return std::any_of(props.begin(), props.end(), [&](const auto& p) { return std::strcmp(p.extensionName, name) == 0; });
}

int computeQueueFamily(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  for (uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && families[i].timestampValidBits > 0) return int(i);
  return -1;
}

std::string versionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

DeviceReport describeDevice(VkPhysicalDevice device, uint32_t index) {
  DeviceReport r;
  r.index = index;
  VkPhysicalDeviceVulkan12Features vulkan12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
                                                       &vulkan12};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &atomics};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &driver};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroup};
  bool atomicExt = hasExtension(device, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  if (!atomicExt) features.pNext = &vulkan12;
  vkGetPhysicalDeviceFeatures2(device, &features);
  vkGetPhysicalDeviceProperties2(device, &props);
  const VkPhysicalDeviceLimits& limits = props.properties.limits;
  r.name = props.properties.deviceName;
  r.type = deviceTypeName(props.properties.deviceType);
  r.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  r.apiVersion = versionString(props.properties.apiVersion);
  r.maxStorageBufferRange = limits.maxStorageBufferRange;
  r.maxComputeWorkGroupCount = limits.maxComputeWorkGroupCount[0];
  r.maxComputeWorkGroupInvocations = limits.maxComputeWorkGroupInvocations;
  r.maxPushConstantsSize = limits.maxPushConstantsSize;
  r.maxPerStageStorageBuffers = limits.maxPerStageDescriptorStorageBuffers;
  r.timestampPeriodNs = limits.timestampPeriod;
  r.floatAtomicAdd = atomicExt && atomics.shaderBufferFloat32AtomicAdd;
  constexpr VkSubgroupFeatureFlags kSubgroupOps = VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  r.subgroupBallotArithmetic = (subgroup.supportedOperations & kSubgroupOps) == kSubgroupOps &&
                         (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0;
  r.int64Atomics = features.features.shaderInt64 && vulkan12.shaderBufferInt64Atomics;
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device, &memory);
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) r.deviceLocalBytes += memory.memoryHeaps[i].size;

  std::vector<std::string> missing;
  if (props.properties.apiVersion < VK_API_VERSION_1_2) missing.push_back("Vulkan 1.2");
  if (!r.floatAtomicAdd) missing.push_back("VK_EXT_shader_atomic_float (shaderBufferFloat32AtomicAdd)");
  // The adjoint passes' gradient accumulators are 64-bit integers (host/adjoint.h).
  if (!r.int64Atomics) missing.push_back("64-bit integer atomics (shaderInt64, shaderBufferInt64Atomics)");
  // ... which a subgroup's lanes that add to the same one may first sum (shaders/lib/adjoint.glsl).
  if (!r.subgroupBallotArithmetic) missing.push_back("subgroup ballot and arithmetic in compute shaders");
  if (computeQueueFamily(device) < 0) missing.push_back("a compute queue with timestamps");
  if (limits.maxPerStageDescriptorStorageBuffers < gpu::kBindingCount) missing.push_back("enough storage-buffer bindings");
  for (const auto& m : missing) r.missing += (r.missing.empty() ? "" : ", ") + m;
  r.usable = missing.empty();
  return r;
}

VkInstance createInstance(bool validation, bool debugUtils) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "vktg";
  app.pEngineName = "vktg";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) layers.push_back(kValidationLayer);
  if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw Error("no Vulkan driver found: install mesa-vulkan-drivers (lavapipe) or a GPU driver (tools/setup does)");
  VKTG_VK_CHECK(result);
  return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  uint32_t count = 0;
  VKTG_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VKTG_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  return devices;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// The usable device a plain choice prefers (a discrete GPU first, lavapipe last); with
// `gpuOnly`, CPU implementations are not candidates. -1 if none.
int preferredDevice(const std::vector<VkPhysicalDevice>& devices, const std::vector<DeviceReport>& reports,
                    bool gpuOnly) {
  int chosen = -1;
  VkPhysicalDeviceType chosenType = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  for (uint32_t i = 0; i < devices.size(); ++i) {
    if (!reports[i].usable) continue;
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    if (gpuOnly && p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) continue;
    if (chosen < 0 || typeRank(p.deviceType) < typeRank(chosenType)) {
      chosen = int(i);
      chosenType = p.deviceType;
    }
  }
  return chosen;
}

}  // namespace

ContextOptions contextOptionsFromEnvironment() {
  ContextOptions options;
  if (const char* device = std::getenv("VKTG_DEVICE")) options.device = device;
  const char* validation = std::getenv("VKTG_VALIDATION");
  options.validation = validation && std::string(validation) == "1";
  return options;
}

std::vector<DeviceReport> VulkanContext::listDevices() {
  VkInstance instance = createInstance(false, false);
  std::vector<DeviceReport> reports;
  try {
    auto devices = physicalDevices(instance);
    for (uint32_t i = 0; i < devices.size(); ++i) reports.push_back(describeDevice(devices[i], i));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return reports;
}

bool labelsAreSafe(uint32_t layerVersion) { return layerVersion == 0 || layerVersion >= VK_MAKE_API_VERSION(0, 1, 3, 243); }

VulkanContext::VulkanContext(const ContextOptions& options) {
  const uint32_t validationVersion = options.validation ? instanceLayerVersion(kValidationLayer) : 0;
  if (options.validation && validationVersion == 0)
    throw Error("validation requested but VK_LAYER_KHRONOS_validation is not installed (package vulkan-validationlayers)");
  bool debugUtils = instanceHasExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  m_instance = createInstance(options.validation, debugUtils);
  try {
    if (debugUtils) {
      m_setName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(vkGetInstanceProcAddr(m_instance, "vkSetDebugUtilsObjectNameEXT"));
      if (labelsAreSafe(validationVersion)) {
        m_beginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(vkGetInstanceProcAddr(m_instance, "vkCmdBeginDebugUtilsLabelEXT"));
        m_endLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(vkGetInstanceProcAddr(m_instance, "vkCmdEndDebugUtilsLabelEXT"));
      }
    }
    if (options.validation && debugUtils) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(m_instance, "vkCreateDebugUtilsMessengerEXT"));
      VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      info.pfnUserCallback = &VulkanContext::onDebugMessage;
      info.pUserData = this;
      VKTG_VK_CHECK(create(m_instance, &info, nullptr, &m_messenger));
    }

    auto devices = physicalDevices(m_instance);
    std::vector<DeviceReport> reports;
    for (uint32_t i = 0; i < devices.size(); ++i) reports.push_back(describeDevice(devices[i], i));
    int chosen = -1;
    if (options.device.empty()) {
      chosen = preferredDevice(devices, reports, false);
      if (chosen < 0) throw Error("no usable Vulkan device (see `vktg info` for what each device lacks)");
    } else if (options.device == "gpu") {
      chosen = preferredDevice(devices, reports, true);
      if (chosen < 0) throw Error("--device gpu: no usable GPU (see `vktg info` for the devices and what they lack)");
    } else {
      bool numeric = std::all_of(options.device.begin(), options.device.end(), ::isdigit);
      for (uint32_t i = 0; i < devices.size() && chosen < 0; ++i) {
        bool match = numeric ? std::to_string(i) == options.device
                             : lower(reports[i].name).find(lower(options.device)) != std::string::npos;
        if (match) chosen = int(i);
      }
      if (chosen < 0) throw Error("--device: no device matches '" + options.device + "' (see `vktg info`)");
      if (!reports[size_t(chosen)].usable)
        throw Error("--device: '" + reports[size_t(chosen)].name + "' lacks " + reports[size_t(chosen)].missing);
    }
    m_physical = devices[size_t(chosen)];
    m_report = reports[size_t(chosen)];
    vkGetPhysicalDeviceProperties(m_physical, &m_properties);
    vkGetPhysicalDeviceMemoryProperties(m_physical, &m_memory);
    m_queueFamily = uint32_t(computeQueueFamily(m_physical));

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = m_queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan12Features vulkan12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    vulkan12.shaderBufferInt64Atomics = VK_TRUE;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
                                                         &vulkan12};
    atomics.shaderBufferFloat32AtomicAdd = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &atomics};
    features.features.shaderInt64 = VK_TRUE;
    const char* extensions[] = {VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME};
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = 1;
    deviceInfo.ppEnabledExtensionNames = extensions;
    VKTG_VK_CHECK(vkCreateDevice(m_physical, &deviceInfo, nullptr, &m_device));
    vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = m_queueFamily;
    VKTG_VK_CHECK(vkCreateCommandPool(m_device, &poolInfo, nullptr, &m_commandPool));
  } catch (...) {
    release();
    throw;
  }
}

namespace {
std::atomic<bool> g_validationFailedAtExit{false};
}  // namespace

bool validationFailedAtExit() { return g_validationFailedAtExit.load(); }

VulkanContext::~VulkanContext() {
  release();
  const std::vector<std::string> late = takeValidationMessages();
  for (const std::string& m : late) std::fprintf(stderr, "vktg: validation at exit: %s\n", m.c_str());
  if (!late.empty()) g_validationFailedAtExit = true;
}

void VulkanContext::release() {
  if (m_stuck) {
    // The device may still use the shared objects: they are kept to the end of the process.
    static auto* keptForTheStuckDevice = new std::vector<std::map<std::string, std::shared_ptr<void>>>;
    keptForTheStuckDevice->push_back(std::move(m_shared));
    return;
  }
  m_shared.clear();
  if (m_device) {
    vkDeviceWaitIdle(m_device);
    if (m_commandPool) vkDestroyCommandPool(m_device, m_commandPool, nullptr);
    vkDestroyDevice(m_device, nullptr);
    m_device = VK_NULL_HANDLE;
  }
  if (m_messenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(m_instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(m_instance, m_messenger, nullptr);
    m_messenger = VK_NULL_HANDLE;
  }
  if (m_instance) {
    vkDestroyInstance(m_instance, nullptr);
    m_instance = VK_NULL_HANDLE;
  }
}

uint32_t VulkanContext::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < m_memory.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (m_memory.memoryTypes[i].propertyFlags & required) == required) return i;
  throw Error("no Vulkan memory type with the required properties");
}

bool VulkanContext::hasMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < m_memory.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (m_memory.memoryTypes[i].propertyFlags & required) == required) return true;
  return false;
}

void VulkanContext::setObjectName(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!m_setName || !handle) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  m_setName(m_device, &info);
}

void VulkanContext::beginLabel(VkCommandBuffer cmd, const char* name) const {
  if (!m_beginLabel) return;
  VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  label.pLabelName = name;
  m_beginLabel(cmd, &label);
}

void VulkanContext::endLabel(VkCommandBuffer cmd) const {
  if (m_endLabel) m_endLabel(cmd);
}

void VulkanContext::submitAndWait(VkCommandBuffer cmd) const {
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VKTG_VK_CHECK(vkCreateFence(m_device, &fenceInfo, nullptr, &fence));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  ++m_submissions;
  VkResult result = m_faults.nextSubmission();
  const bool injected = result != VK_SUCCESS;
  if (!injected) result = vkQueueSubmit(m_queue, 1, &submit, fence);
  if (result == VK_SUCCESS) result = vkWaitForFences(m_device, 1, &fence, VK_TRUE, kFenceTimeoutNs);
  if (result == VK_TIMEOUT) {
    // The fence may still be signalled later: destroying it (or anything the work uses) now would
    // be undefined, so it is left for the process exit. An injected timeout submitted nothing.
    if (!injected) m_stuck = true;
    else vkDestroyFence(m_device, fence, nullptr);
    throw DeviceFault(m_report.name + ": a GPU submission did not finish within " +
                      std::to_string(kFenceTimeoutNs / 1000000000) +
                      " s (fence timeout); the device is stuck or the batch is far too large (a smaller --mem "
                      "makes smaller batches)");
  }
  vkDestroyFence(m_device, fence, nullptr);
  if (result == VK_SUCCESS && memoryGuardsOn()) checkMemoryGuards();
  if (result == VK_ERROR_DEVICE_LOST)
    throw DeviceFault(m_report.name + ": the Vulkan device was lost (VK_ERROR_DEVICE_LOST): the driver reset it "
                      "after a fault or a kernel that ran too long; nothing of this run can be trusted");
  VKTG_VK_CHECK(result);
}

VkResult VulkanContext::allocateMemory(const VkMemoryAllocateInfo& info, VkDeviceMemory* memory) const {
  ++m_allocations;
  VkResult injected = m_faults.nextAllocation();
  if (injected != VK_SUCCESS) return injected;
  if (m_faults.nextAllocationLeaks()) {
    VkMemoryAllocateInfo block = info;
    block.allocationSize = 256;
    VkDeviceMemory leaked = VK_NULL_HANDLE;
    VKTG_VK_CHECK(vkAllocateMemory(m_device, &block, nullptr, &leaked));  // never freed, on purpose
  }
  return vkAllocateMemory(m_device, &info, nullptr, memory);
}

std::vector<std::string> VulkanContext::destroyAndTakeValidationMessages() {
  release();
  return takeValidationMessages();
}

std::vector<std::string> VulkanContext::takeValidationMessages() {
  std::lock_guard lock(m_messageMutex);
  return std::exchange(m_messages, {});
}

VkBool32 VulkanContext::onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<VulkanContext*>(user);
  std::lock_guard lock(self->m_messageMutex);
  self->m_messages.emplace_back(data->pMessage ? data->pMessage : "(no message)");
  self->m_messageCount++;
  return VK_FALSE;
}

}  // namespace vktg
