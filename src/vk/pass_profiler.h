// Timestamps around every dispatch, accumulated per pass name, for `--profile` and the benchmarks;
// disabled, it only labels the scopes (timestamps cost a few ms per render on lavapipe).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "vk/vk_resources.h"

namespace vktg {

class PassProfiler {
 public:
  PassProfiler(const VulkanContext& context, uint32_t maxScopesPerSubmit, bool enabled = true);
  // Starts a labelled, timed scope in `cmd` (debug label + timestamp); end() closes the last one.
  void begin(VkCommandBuffer cmd, const char* pass);
  void end(VkCommandBuffer cmd);
  void reset(VkCommandBuffer cmd);  // before the first scope of a command buffer
  void collect();                   // after the submit finished: adds the times per pass
  const std::map<std::string, double>& millisecondsPerPass() const { return m_totals; }
  const std::map<std::string, uint64_t>& dispatchesPerPass() const { return m_counts; }

 private:
  const VulkanContext& m_context;
  QueryPool m_pool;
  uint32_t m_capacity;
  std::vector<std::string> m_open;  // names of the scopes recorded since reset
  std::vector<bool> m_timed;        // per open scope: whether it got timestamps
  std::map<std::string, double> m_totals;
  std::map<std::string, uint64_t> m_counts;
};

}  // namespace vktg
