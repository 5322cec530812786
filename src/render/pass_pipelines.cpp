#include "render/pass_pipelines.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>
#include <thread>
#include <unistd.h>
#include <fstream>
#include <iterator>
#include <vector>

#include "vk/forced_choice.h"
#include "vk/vk_check.h"
#include "vktg/error.h"

namespace vktg {
namespace {

std::vector<char> readFileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

PassPipelines::PassPipelines(const VulkanContext& context, const ShaderTable& shaders, std::filesystem::path cacheFile,
                             uint32_t bindingCount)
    : m_context(context), m_shaders(shaders), m_cacheFile(std::move(cacheFile)), m_bindingCount(bindingCount) {
  if (bindingCount > gpu::kBindingCount) throw Error("internal: a pass layout has more bindings than BindingTable holds");
  VkDevice device = context.device();
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (uint32_t b = 0; b < bindingCount; ++b) {
    VkDescriptorSetLayoutBinding binding{};
    binding.binding = b;
    binding.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    binding.descriptorCount = 1;
    binding.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    bindings.push_back(binding);
  }
  for (uint32_t k = 0; k < gpu::kTexelBindingCount; ++k)
    bindings.push_back(
        {gpu::kFirstTexelBinding + k, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.bindingCount = uint32_t(bindings.size());
  setInfo.pBindings = bindings.data();
  VkDescriptorSetLayout setLayout;
  VKTG_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout));
  m_setLayout = DescriptorSetLayout(device, setLayout);

  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::PassPush)};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout;
  layoutInfo.pushConstantRangeCount = 1;
  layoutInfo.pPushConstantRanges = &push;
  VkPipelineLayout layout;
  VKTG_VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout));
  m_layout = PipelineLayout(device, layout);

  // A stale or foreign cache is rejected by the driver itself (its header names vendor, device
  // and cache UUID), so reading whatever is on disk is safe.
  std::vector<char> initial = m_cacheFile.empty() ? std::vector<char>{} : readFileBytes(m_cacheFile);
  VkPipelineCacheCreateInfo cacheInfo{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  cacheInfo.initialDataSize = initial.size();
  cacheInfo.pInitialData = initial.empty() ? nullptr : initial.data();
  VkPipelineCache cache;
  if (vkCreatePipelineCache(device, &cacheInfo, nullptr, &cache) != VK_SUCCESS) {
    cacheInfo.initialDataSize = 0;
    cacheInfo.pInitialData = nullptr;
    VKTG_VK_CHECK(vkCreatePipelineCache(device, &cacheInfo, nullptr, &cache));
  }
  m_cache = PipelineCache(device, cache);
}

PassPipelines::~PassPipelines() {
  if (m_cacheFile.empty() || !m_cache) return;
  size_t size = 0;
  if (vkGetPipelineCacheData(m_context.device(), m_cache.get(), &size, nullptr) != VK_SUCCESS || size == 0) return;
  std::vector<char> data(size);
  if (vkGetPipelineCacheData(m_context.device(), m_cache.get(), &size, data.data()) != VK_SUCCESS) return;
  // Best effort: a cache that cannot be written only costs compile time next run.
  std::error_code ec;
  std::filesystem::create_directories(m_cacheFile.parent_path(), ec);
  std::filesystem::path tmp = m_cacheFile;
  tmp += ".tmp" + std::to_string(::getpid());
  std::ofstream out(tmp, std::ios::binary);
  out.write(data.data(), std::streamsize(size));
  out.close();
  if (out) std::filesystem::rename(tmp, m_cacheFile, ec);
  else std::filesystem::remove(tmp, ec);
}

VkShaderModule PassPipelines::module(const std::string& shader) {
  auto it = m_modules.find(shader);
  if (it == m_modules.end()) {
    auto code = m_shaders.find(shader);
    if (code == m_shaders.end()) throw Error("internal: no embedded shader named '" + shader + "'");
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = code->second.size() * sizeof(uint32_t);
    info.pCode = code->second.data();
    VkShaderModule module;
    VKTG_VK_CHECK(vkCreateShaderModule(m_context.device(), &info, nullptr, &module));
    m_context.setObjectName(VK_OBJECT_TYPE_SHADER_MODULE, uint64_t(module), shader);
    it = m_modules.emplace(shader, ShaderModule(m_context.device(), module)).first;
  }
  return it->second.get();
}

std::shared_ptr<PassPipelines> PassPipelines::shared(VulkanContext& context, const ShaderTable& shaders,
                                                     const std::filesystem::path& cacheFile, uint32_t bindingCount) {
  const std::string key = "pass-pipelines " + std::to_string(reinterpret_cast<uintptr_t>(&shaders)) + " " +
                          std::to_string(bindingCount) + " " + cacheFile.string();
  return context.shared<PassPipelines>(
      key, [&] { return std::make_shared<PassPipelines>(context, shaders, cacheFile, bindingCount); });
}

void PassPipelines::prepare(const std::vector<std::pair<std::string, SpecValues>>& passes) {
  std::lock_guard lock(m_mutex);
  prepareLocked(passes);
}

void PassPipelines::prepareLocked(const std::vector<std::pair<std::string, SpecValues>>& passes) {
  std::vector<std::pair<std::string, SpecValues>> missing;
  for (const auto& key : passes)
    if (!m_pipelines.count(key) && std::find(missing.begin(), missing.end(), key) == missing.end()) missing.push_back(key);
  if (missing.empty()) return;
  std::array<VkSpecializationMapEntry, gpu::kSpecCount> entries{};
  for (uint32_t i = 0; i < gpu::kSpecCount; ++i) entries[i] = {i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)};
  const size_t n = missing.size();
  std::vector<VkSpecializationInfo> specInfos(n);
  std::vector<VkComputePipelineCreateInfo> infos(n, {VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO});
  for (size_t k = 0; k < n; ++k) {
    specInfos[k] = {gpu::kSpecCount, entries.data(), sizeof(SpecValues), missing[k].second.data()};
    infos[k].stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    infos[k].stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    infos[k].stage.module = module(missing[k].first);
    infos[k].stage.pName = "main";
    infos[k].stage.pSpecializationInfo = &specInfos[k];
    infos[k].layout = m_layout.get();
  }
  // On a GPU, one thread per pipeline: vkCreateComputePipelines may be called concurrently, and the
  // pipeline cache synchronises itself (it was not created externally synchronised). A thread that
  // cannot be started leaves its pipeline to this one. On a CPU device, one after another: lavapipe
  // (Mesa 22.3) makes each pipeline's shader through its queue's gallium context, which is not made
  // for several threads at once, and valgrind's helgrind sees the creating threads read and write
  // lavapipe's globals unsynchronised (a CI run's vktg died of a segmentation fault in its start-up;
  // the heap corruptions seen beside it came from the validation layer's labels instead:
  // docs/robustness.md, "Threads").
  // VKTG_PIPELINE_CREATION=parallel|serial overrides.
  std::vector<VkPipeline> created(n, VK_NULL_HANDLE);
  std::vector<VkResult> results(n, VK_SUCCESS);
  auto create = [&](size_t k) {
    results[k] = vkCreateComputePipelines(m_context.device(), m_cache.get(), 1, &infos[k], nullptr, &created[k]);
  };
  const bool parallel = forcedChoice("VKTG_PIPELINE_CREATION", "parallel", "serial").value_or(!m_context.isCpuDevice());
  {
    std::vector<std::thread> threads;
    std::vector<size_t> onThisThread;
    for (size_t k = 1; k < n; ++k) {
      if (!parallel) {
        onThisThread.push_back(k);
        continue;
      }
      try {
        threads.emplace_back(create, k);
      } catch (const std::system_error&) {
        onThisThread.push_back(k);
      }
    }
    create(0);
    for (size_t k : onThisThread) create(k);
    for (std::thread& t : threads) t.join();
  }
  // Keep whatever was created (destroyed with the others) before reporting a failure.
  for (size_t k = 0; k < n; ++k)
    if (results[k] == VK_SUCCESS) {
      m_context.setObjectName(VK_OBJECT_TYPE_PIPELINE, uint64_t(created[k]), missing[k].first);
      m_pipelines.emplace(missing[k], Pipeline(m_context.device(), created[k]));
    }
  for (VkResult result : results) VKTG_VK_CHECK(result);
}

size_t PassPipelines::size() {
  std::lock_guard lock(m_mutex);
  return m_pipelines.size();
}

VkPipeline PassPipelines::get(const std::string& shader, const SpecValues& spec) {
  std::lock_guard lock(m_mutex);
  auto key = std::make_pair(shader, spec);
  if (auto it = m_pipelines.find(key); it == m_pipelines.end()) prepareLocked({key});
  return m_pipelines.at(key).get();
}

void BindingTable::setChunks(uint32_t firstBinding, const ChunkedBuffer& chunked) {
  for (size_t c = 0; c < chunked.chunks.size() && c < gpu::kMaxBufferChunks; ++c)
    buffers[firstBinding + c] = chunked.chunks[c].handle();
}

void BindingTable::setScene(const GpuScene& scene) {
  setChunks(gpu::kBindingTriangles, scene.triangles);
  setChunks(gpu::kBindingBvhNodes, scene.bvhNodes);
  setTexels(gpu::kBindingTriangleTexels, scene.triangleTexels);
  setTexels(gpu::kBindingBvhNodeTexels, scene.bvhNodeTexels);
  setTexels(gpu::kBindingWideBvhTexels, scene.wideBvhTexels);
  set(gpu::kBindingTriangleVerts, scene.triangleVerts);
  set(gpu::kBindingVertices, scene.vertices);
  set(gpu::kBindingShapes, scene.shapes);
  set(gpu::kBindingMaterials, scene.materials);
  set(gpu::kBindingLights, scene.lights);
}

DescriptorSet::DescriptorSet(const VulkanContext& context, const PassPipelines& pipelines, const BindingTable& table,
                             const Buffer& dummy) {
  VkDevice device = context.device();
  const uint32_t count = pipelines.bindingCount();
  VkDescriptorSetLayout layout = pipelines.setLayout();
  VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, count},
                                  {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, gpu::kTexelBindingCount}};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 2;
  poolInfo.pPoolSizes = sizes;
  VkDescriptorPool pool;
  VKTG_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool));
  m_pool = DescriptorPool(device, pool);
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  VKTG_VK_CHECK(vkAllocateDescriptorSets(device, &alloc, &m_set));

  std::array<VkDescriptorBufferInfo, gpu::kBindingCount> infos{};
  std::array<VkWriteDescriptorSet, gpu::kBindingCount + gpu::kTexelBindingCount> writes{};
  for (uint32_t b = 0; b < count; ++b) {
    infos[b] = {table.buffers[b] ? table.buffers[b] : dummy.handle(), 0, VK_WHOLE_SIZE};
    writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[b].dstSet = m_set;
    writes[b].dstBinding = b;
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  // Texel bindings the table leaves empty (passes or scenes that load through storage buffers)
  // view the dummy buffer.
  std::array<VkBufferView, gpu::kTexelBindingCount> views = table.texels;
  for (VkBufferView& view : views) {
    if (view) continue;
    if (!m_dummyView) m_dummyView = texelView(context, dummy, "dummy.texels");
    view = m_dummyView.get();
  }
  for (uint32_t k = 0; k < gpu::kTexelBindingCount; ++k) {
    VkWriteDescriptorSet& w = writes[count + k];
    w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = m_set;
    w.dstBinding = gpu::kFirstTexelBinding + k;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    w.pTexelBufferView = &views[k];
  }
  vkUpdateDescriptorSets(device, count + gpu::kTexelBindingCount, writes.data(), 0, nullptr);
}

std::filesystem::path defaultPipelineCacheFile(const VulkanContext& context) {
  std::filesystem::path base;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) base = xdg;
  else if (const char* home = std::getenv("HOME"); home && *home) base = std::filesystem::path(home) / ".cache";
  else return {};
  const auto& p = context.properties();
  return base / "vktg" / ("pipelines-" + std::to_string(p.vendorID) + "-" + std::to_string(p.deviceID) + "-" +
                          std::to_string(p.driverVersion) + ".bin");
}

}  // namespace vktg
