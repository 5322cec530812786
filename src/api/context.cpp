// vktg::Context: the public face of a VulkanContext, its device chosen by DeviceOptions alone (the
// library reads no environment variables for it; the command line does, for its defaults).
#include "api/context_impl.h"
#include "render/memory_preflight.h"

namespace vktg {

Context::Context(const DeviceOptions& options) : m_impl(std::make_unique<Impl>(options)) {}
Context::~Context() = default;

std::string Context::deviceName() const { return m_impl->vulkan.report().name; }
bool Context::cpuDevice() const { return m_impl->vulkan.isCpuDevice(); }
uint64_t Context::memoryBudget() const {
  return m_impl->options.memoryBudget ? m_impl->options.memoryBudget : defaultMemoryBudget(m_impl->vulkan);
}
size_t Context::validationMessages() const { return size_t(m_impl->vulkan.validationMessageCount()); }

}  // namespace vktg
