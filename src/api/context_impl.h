// What a vktg::Context holds: the device and the renderer of every call made with it.
#pragma once
#include "render/renderer.h"
#include "vk/vk_context.h"
#include "vktg/vktg.h"

namespace vktg {

struct Context::Impl {
  explicit Impl(const DeviceOptions& o) : vulkan(ContextOptions{o.device, o.validation}), options(o), renderer(vulkan) {}
  VulkanContext vulkan;
  DeviceOptions options;
  Renderer renderer;
};

}  // namespace vktg
