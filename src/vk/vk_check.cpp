#include "vk/vk_check.h"

namespace vktg {

const char* vkResultName(VkResult result) {
  switch (result) {
#define VKTG_RESULT_CASE(name) case name: return #name;
    VKTG_RESULT_CASE(VK_SUCCESS)
    VKTG_RESULT_CASE(VK_NOT_READY)
    VKTG_RESULT_CASE(VK_TIMEOUT)
    VKTG_RESULT_CASE(VK_INCOMPLETE)
    VKTG_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    VKTG_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    VKTG_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    VKTG_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    VKTG_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    VKTG_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    VKTG_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    VKTG_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    VKTG_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    VKTG_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    VKTG_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    VKTG_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    VKTG_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    VKTG_RESULT_CASE(VK_ERROR_INVALID_SHADER_NV)
#undef VKTG_RESULT_CASE
    default: return "VK_ERROR_(unknown)";
  }
}

VulkanError::VulkanError(VkResult result, const char* expression, const char* file, int line)
    : std::runtime_error(std::string("Vulkan call failed with ") + vkResultName(result) + ": " + expression +
                         " (" + file + ":" + std::to_string(line) + ")"),
      m_result(result) {}

}  // namespace vktg
