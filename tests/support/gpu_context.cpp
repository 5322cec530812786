#include "support/gpu_context.h"

#include "support/test_environment.h"

#include <cstdlib>
#include <memory>
#include <string>

#include <gtest/gtest.h>

namespace vktg::test {
namespace {

std::unique_ptr<VulkanContext>& contextSlot() {
  static std::unique_ptr<VulkanContext> context;
  return context;
}

// Turns validation messages into test failures, attributed to the test that caused them.
class ValidationListener : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo&) override {
    auto& context = contextSlot();
    if (!context) return;
    for (const std::string& message : context->takeValidationMessages())
      ADD_FAILURE() << "Vulkan validation message: " << message;
  }
};

const bool kListenerInstalled = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new ValidationListener);
  return true;
}();

}  // namespace

VulkanContext& testContext() {
  auto& context = contextSlot();
  if (!context) {
    applyTestEnvironment();
    ContextOptions options;
    const char* validation = std::getenv("VKTG_VALIDATION");
    options.validation = validation && std::string(validation) == "1";
    if (const char* device = std::getenv("VKTG_TEST_DEVICE")) options.device = device;
    context = std::make_unique<VulkanContext>(options);
  }
  (void)kListenerInstalled;
  return *context;
}

}  // namespace vktg::test
