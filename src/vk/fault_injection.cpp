#include "vk/fault_injection.h"

#include <cstdlib>
#include <string>
#include <sstream>
#include <vector>

#include "vktg/error.h"

namespace vktg {

FaultInjection::FaultInjection(const char* text) {
  if (!text || !*text) return;
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ':');) parts.push_back(part);
  char* end = nullptr;
  unsigned long long at = parts.size() >= 2 ? std::strtoull(parts[1].c_str(), &end, 10) : 0;
  bool number = at > 0 && end && *end == '\0';
  if (number && parts.size() == 2 && parts[0] == "alloc") m_kind = Kind::Allocation;
  else if (number && parts.size() == 3 && parts[0] == "submit" && parts[2] == "lost") m_kind = Kind::DeviceLost;
  else if (number && parts.size() == 3 && parts[0] == "submit" && parts[2] == "timeout") m_kind = Kind::FenceTimeout;
  else if (number && parts.size() == 2 && parts[0] == "leak") m_kind = Kind::Leak;
  else fail("VKTG_INJECT_FAULT", "", "'" + std::string(text) + "' is not alloc:N, submit:N:lost, submit:N:timeout or leak:N");
  m_at = at;
}

VkResult FaultInjection::nextAllocation() {
  if (m_kind != Kind::Allocation) return VK_SUCCESS;
  return ++m_allocations == m_at ? VK_ERROR_OUT_OF_DEVICE_MEMORY : VK_SUCCESS;
}

bool FaultInjection::nextAllocationLeaks() { return m_kind == Kind::Leak && ++m_allocations == m_at; }

VkResult FaultInjection::nextSubmission() {
  if (m_kind != Kind::DeviceLost && m_kind != Kind::FenceTimeout) return VK_SUCCESS;
  if (++m_submissions != m_at) return VK_SUCCESS;
  return m_kind == Kind::DeviceLost ? VK_ERROR_DEVICE_LOST : VK_TIMEOUT;
}

}  // namespace vktg
