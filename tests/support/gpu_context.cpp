#include "support/gpu_context.h"

#include "support/test_environment.h"

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace vktg::test {
namespace {

struct SharedGpu {
  std::unique_ptr<VulkanContext> context;
  std::vector<std::function<void()>> dependents;

  void release() {
    while (!dependents.empty()) {
      std::function<void()> destroy = std::move(dependents.back());
      dependents.pop_back();
      destroy();
    }
    if (!context) return;
    // Objects never destroyed are reported by the validation layer when the device goes.
    for (const std::string& message : context->destroyAndTakeValidationMessages())
      ADD_FAILURE() << "Vulkan validation message at teardown: " << message;
    context.reset();
  }

  ~SharedGpu() {
    if (!context) return;
    std::fprintf(stderr, "test support: the Vulkan test context outlived the test program (destroying it now "
                         "would run after the driver's exit handlers)\n");
    std::abort();
  }
};

SharedGpu& shared() {
  static SharedGpu gpu;
  return gpu;
}

// Turns validation messages into test failures, attributed to the test that caused them.
class ValidationListener : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo&) override {
    auto& context = shared().context;
    if (!context) return;
    for (const std::string& message : context->takeValidationMessages())
      ADD_FAILURE() << "Vulkan validation message: " << message;
  }
};

// Global environments are torn down at the end of RUN_ALL_TESTS, i.e. before main returns.
class ReleaseGpuAtEnd : public ::testing::Environment {
  void TearDown() override { shared().release(); }
};

const bool kHooksInstalled = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new ValidationListener);
  ::testing::AddGlobalTestEnvironment(new ReleaseGpuAtEnd);
  return true;
}();

}  // namespace

VulkanContext& testContext() {
  auto& context = shared().context;
  if (!context) {
    applyTestEnvironment();
    context = std::make_unique<VulkanContext>(contextOptionsFromEnvironment());
  }
  (void)kHooksInstalled;
  return *context;
}

void destroyBeforeTestContext(std::function<void()> destroy) { shared().dependents.push_back(std::move(destroy)); }

}  // namespace vktg::test
