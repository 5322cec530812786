// Test hook for device faults that cannot be provoked on purpose (an exhausted device, a lost
// device, a stuck queue). VKTG_INJECT_FAULT names one fault for the process:
//   alloc:N          the N-th device memory allocation fails (VK_ERROR_OUT_OF_DEVICE_MEMORY)
//   submit:N:lost    the N-th queue submission reports VK_ERROR_DEVICE_LOST
//   submit:N:timeout the N-th queue submission never signals its fence (a fence timeout)
//   leak:N           the N-th device memory allocation also allocates a block nobody frees (so
//                    that the validation layer's report at device destruction can be tested)
// (N counts from 1 per VulkanContext). Unset: no fault, and nothing is counted.
#pragma once
#include <atomic>
#include <cstdint>
#include <string>

#include <vulkan/vulkan.h>

namespace vktg {

class FaultInjection {
 public:
  // `spec`: the value of VKTG_INJECT_FAULT (null or empty: none); a malformed one is an error
  // naming the variable.
  explicit FaultInjection(const char* spec);

  // VK_SUCCESS, or the injected failure of this allocation / submission.
  VkResult nextAllocation();
  VkResult nextSubmission();
  // Whether this allocation is the one that leaks (leak:N); counts allocations like nextAllocation.
  bool nextAllocationLeaks();

 private:
  enum class Kind { None, Allocation, DeviceLost, FenceTimeout, Leak };
  Kind m_kind = Kind::None;
  uint64_t m_at = 0;
  std::atomic<uint64_t> m_allocations{0}, m_submissions{0};
};

}  // namespace vktg
