// `vktg info`: the Vulkan devices, whether vktg can use each, and the limits it relies on.
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "vk/vk_context.h"

namespace vktg::cli {

const CommandSpec& infoSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "info";
    s.usage = "info";
    s.description = "Lists the Vulkan devices, the features vktg needs and the limits it works within.";
    s.options = {{"--help", "", "show this help"}};
    s.maxPositionals = 0;
    return s;
  }();
  return spec;
}

int runInfo(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(infoSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(infoSpec());
    return 0;
  }
  auto devices = VulkanContext::listDevices();
  if (devices.empty()) std::printf("no Vulkan devices\n");
  for (const DeviceReport& d : devices) {
    std::printf("[%u] %s (%s), Vulkan %s, driver %s\n", d.index, d.name.c_str(), d.type.c_str(), d.apiVersion.c_str(),
                d.driver.c_str());
    std::printf("    usable by vktg: %s\n", d.usable ? "yes" : ("no, lacks " + d.missing).c_str());
    std::printf("    float atomic add (VK_EXT_shader_atomic_float): %s\n", d.floatAtomicAdd ? "yes" : "no");
    std::printf("    subgroup ballot and arithmetic: %s\n", d.subgroupBallotArithmetic ? "yes" : "no");
    std::printf("    maxStorageBufferRange: %llu bytes (larger buffers are split)\n", (unsigned long long)d.maxStorageBufferRange);
    std::printf("    maxComputeWorkGroupCount[0]: %u, maxComputeWorkGroupInvocations: %u\n", d.maxComputeWorkGroupCount,
                d.maxComputeWorkGroupInvocations);
    std::printf("    maxPerStageDescriptorStorageBuffers: %u (vktg binds %u), maxPushConstantsSize: %u\n",
                d.maxPerStageStorageBuffers, gpu::kBindingCount, d.maxPushConstantsSize);
    std::printf("    device-local memory: %.1f GiB, timestamp period: %.3g ns\n", double(d.deviceLocalBytes) / (1u << 30),
                d.timestampPeriodNs);
  }
  return 0;
}

}  // namespace vktg::cli
