// VKTG_VK_CHECK: every VkResult is checked; failures throw with the result's name and call site.
#pragma once
#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace vktg {

const char* vkResultName(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const char* expression, const char* file, int line);
  VkResult result() const { return m_result; }

 private:
  VkResult m_result;
};

}  // namespace vktg

#define VKTG_VK_CHECK(expr)                                                   \
  do {                                                                        \
    VkResult vktgResult_ = (expr);                                            \
    if (vktgResult_ != VK_SUCCESS)                                            \
      throw ::vktg::VulkanError(vktgResult_, #expr, __FILE__, __LINE__);      \
  } while (false)
