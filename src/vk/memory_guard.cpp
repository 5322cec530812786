#include "vk/memory_guard.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include "vktg/error.h"

namespace vktg {
namespace {

constexpr unsigned char kPattern = 0xA5;

struct Guard {
  VkDeviceMemory memory;
  const unsigned char* start;
  size_t bytes;
  std::string bufferName;
};

// Buffers are made and freed on one thread, but the registry is cheap to keep safe.
std::mutex g_mutex;
std::vector<Guard> g_guards;

}  // namespace

bool memoryGuardsOn() {
  static const bool on = [] {
    const char* value = std::getenv("VKTG_GUARD_MEMORY");
    return value && std::string(value) == "1";
  }();
  return on;
}

void guardMemory(VkDeviceMemory memory, void* start, size_t bytes, const std::string& bufferName) {
  std::memset(start, kPattern, bytes);
  std::lock_guard<std::mutex> lock(g_mutex);
  g_guards.push_back({memory, static_cast<const unsigned char*>(start), bytes, bufferName});
}

void releaseMemoryGuards(VkDeviceMemory memory) {
  std::lock_guard<std::mutex> lock(g_mutex);
  std::erase_if(g_guards, [&](const Guard& g) { return g.memory == memory; });
}

void checkMemoryGuards() {
  std::lock_guard<std::mutex> lock(g_mutex);
  for (const Guard& g : g_guards) {
    const unsigned char* end = g.start + g.bytes;
    const unsigned char* bad = std::find_if(g.start, end, [](unsigned char b) { return b != kPattern; });
    if (bad != end)
      throw Error("device memory guard: something wrote past the end of buffer '" + g.bufferName + "' (byte " +
                  std::to_string(bad - g.start) + " after it); the run's results cannot be trusted");
  }
}

}  // namespace vktg
