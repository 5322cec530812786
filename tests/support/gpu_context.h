// The Vulkan context shared by all GPU tests of one test binary: lavapipe (selected by ctest's
// VK_DRIVER_FILES), validation on when VKTG_VALIDATION=1 (ctest sets it). A listener fails any
// test during which the validation layer printed a message.
#pragma once
#include "host/vk_context.h"

namespace vktg::test {
VulkanContext& testContext();
}  // namespace vktg::test
