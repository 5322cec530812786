// A descriptor-set layout and pipeline layout shared by a family of passes (the render passes use
// gpu::kBindingCount bindings, the scene-update passes gpu::kUpdateBindingCount; all are storage
// buffers, the frame block at binding 0 included, see shaders/lib/scene_bindings.glsl, and both
// add gpu::kTexelBindingCount uniform texel buffers from gpu::kFirstTexelBinding), compute
// pipelines created on demand per (shader variant, specialisation constants), those a render needs
// together (in parallel on a GPU), and descriptor sets.
// Pipelines are cached on disk (VkPipelineCache) keyed by device, driver and vktg build, and in
// memory for the context's lifetime (shared()): every renderer and scene update on one context
// uses the same pipelines, so a process that renders many scenes (an optimisation's restarts, a
// Python session, a benchmark) compiles each variant once. Thread-safe.
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "render/gpu_scene.h"
#include "vk/vk_resources.h"
#include "vktg/shader_registry.h"

namespace vktg {

using SpecValues = std::array<uint32_t, gpu::kSpecCount>;

class PassPipelines {
 public:
  PassPipelines(const VulkanContext& context, const ShaderTable& shaders, std::filesystem::path cacheFile = {},
                uint32_t bindingCount = gpu::kBindingCount);
  ~PassPipelines();
  // The context's one PassPipelines for this shader table, cache file and binding count.
  static std::shared_ptr<PassPipelines> shared(VulkanContext& context, const ShaderTable& shaders,
                                               const std::filesystem::path& cacheFile,
                                               uint32_t bindingCount = gpu::kBindingCount);
  PassPipelines(const PassPipelines&) = delete;
  PassPipelines& operator=(const PassPipelines&) = delete;

  VkPipeline get(const std::string& shader, const SpecValues& spec);

  // Creates the pipelines of `passes` that do not exist yet: in parallel on a GPU (a driver that
  // compiles at creation then uses every core), one after another on a CPU device (the .cpp says
  // why); get() then finds them.
  void prepare(const std::vector<std::pair<std::string, SpecValues>>& passes);
  VkPipelineLayout layout() const { return m_layout.get(); }
  VkDescriptorSetLayout setLayout() const { return m_setLayout.get(); }
  uint32_t bindingCount() const { return m_bindingCount; }
  size_t size();  // pipelines created so far

 private:
  void prepareLocked(const std::vector<std::pair<std::string, SpecValues>>& passes);
  VkShaderModule module(const std::string& shader);
  const VulkanContext& m_context;
  const ShaderTable& m_shaders;
  std::filesystem::path m_cacheFile;
  uint32_t m_bindingCount;
  DescriptorSetLayout m_setLayout;
  PipelineLayout m_layout;
  PipelineCache m_cache;
  std::map<std::string, ShaderModule> m_modules;
  std::map<std::pair<std::string, SpecValues>, Pipeline> m_pipelines;
  std::mutex m_mutex;  // over the maps: renderers on several threads may share this object
};

// What each binding of set 0 points at; unset bindings get a small dummy buffer.
struct BindingTable {
  std::array<VkBuffer, gpu::kBindingCount> buffers{};
  std::array<VkBufferView, gpu::kTexelBindingCount> texels{};  // bindings kFirstTexelBinding + k
  void set(uint32_t binding, const Buffer& buffer) { buffers[binding] = buffer.handle(); }
  void setTexels(uint32_t binding, const BufferView& view) { texels[binding - gpu::kFirstTexelBinding] = view.get(); }
  void setChunks(uint32_t firstBinding, const ChunkedBuffer& chunked);
  void setScene(const GpuScene& scene);
};

class DescriptorSet {
 public:
  DescriptorSet(const VulkanContext& context, const PassPipelines& pipelines, const BindingTable& table, const Buffer& dummy);
  DescriptorSet(DescriptorSet&&) = default;
  DescriptorSet& operator=(DescriptorSet&&) = default;
  VkDescriptorSet get() const { return m_set; }

 private:
  BufferView m_dummyView;
  DescriptorPool m_pool;
  VkDescriptorSet m_set = VK_NULL_HANDLE;
};

// Default on-disk location of the pipeline cache ($XDG_CACHE_HOME/vktg or ~/.cache/vktg).
std::filesystem::path defaultPipelineCacheFile(const VulkanContext& context);

}  // namespace vktg
