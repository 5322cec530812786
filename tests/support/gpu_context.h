// The Vulkan context shared by all GPU tests of one test binary, on the device the test
// environment picks (support/test_environment.h), validation on when VKTG_VALIDATION=1. A
// listener fails any test during which the validation layer printed a message.
//
// Lifetime: the context and everything built on it are destroyed when the tests end, inside
// main, while the driver and the validation layer are still loaded. Objects left for static
// destruction would be destroyed after the driver's own exit handlers have run (the driver is
// loaded after the first test starts, so its handlers run first), which crashes some drivers at
// exit; a context still alive at static destruction therefore aborts the binary, on every driver.
#pragma once
#include <functional>

#include "vk/vk_context.h"

namespace vktg::test {
VulkanContext& testContext();

// Registers how to destroy a shared object built on testContext() (a Renderer, say); such objects
// are destroyed newest first, before the context.
void destroyBeforeTestContext(std::function<void()> destroy);
}  // namespace vktg::test
