#include "vk/pass_profiler.h"

#include "vk/vk_check.h"

namespace vktg {

PassProfiler::PassProfiler(const VulkanContext& context, uint32_t maxScopesPerSubmit, bool enabled)
    : m_context(context), m_capacity(enabled ? maxScopesPerSubmit : 0) {
  if (!enabled) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * maxScopesPerSubmit;
  VkQueryPool pool;
  VKTG_VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &pool));
  m_pool = QueryPool(context.device(), pool);
}

void PassProfiler::reset(VkCommandBuffer cmd) {
  if (m_capacity > 0) vkCmdResetQueryPool(cmd, m_pool.get(), 0, 2 * m_capacity);
  m_open.clear();
}

void PassProfiler::begin(VkCommandBuffer cmd, const char* pass) {
  m_context.beginLabel(cmd, pass);
  m_timed.push_back(m_open.size() < m_capacity);
  if (!m_timed.back()) return;  // untimed beyond capacity, still labelled
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_pool.get(), uint32_t(2 * m_open.size()));
  m_open.emplace_back(pass);
}

void PassProfiler::end(VkCommandBuffer cmd) {
  bool timed = m_timed.back();
  m_timed.pop_back();
  m_context.endLabel(cmd);
  if (!timed) return;
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_pool.get(), uint32_t(2 * m_open.size() - 1));
}

void PassProfiler::collect() {
  if (m_open.empty()) return;
  std::vector<uint64_t> stamps(2 * m_open.size());
  VKTG_VK_CHECK(vkGetQueryPoolResults(m_context.device(), m_pool.get(), 0, uint32_t(stamps.size()),
                                      stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                                      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  double period = m_context.properties().limits.timestampPeriod;
  for (size_t i = 0; i < m_open.size(); ++i) {
    uint64_t start = stamps[2 * i], stop = stamps[2 * i + 1];
    m_totals[m_open[i]] += stop > start ? double(stop - start) * period * 1e-6 : 0.0;
    m_counts[m_open[i]]++;
  }
  m_open.clear();
}

}  // namespace vktg
