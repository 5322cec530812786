#include "render/gpu_scene.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdlib>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "vk/forced_choice.h"
#include "vk/vk_check.h"
#include "vktg/error.h"

namespace vktg {
namespace {

template <class T>
Buffer uploadArray(const VulkanContext& context, const std::vector<T>& data, const std::string& name) {
  Buffer buffer(context, std::max<size_t>(data.size() * sizeof(T), 16), MemoryKind::Device, name);
  buffer.upload(context, data.data(), data.size() * sizeof(T));
  return buffer;
}

}  // namespace

uint32_t chunkShiftFor(size_t elementSize, size_t count, uint64_t maxRange, const std::string& what) {
  uint64_t elementsPerRange = std::max<uint64_t>(1, maxRange / elementSize);
  uint32_t shift = 31;
  while (shift > 0 && (uint64_t(1) << shift) > elementsPerRange) --shift;
  uint64_t capacity = (uint64_t(1) << shift) * gpu::kMaxBufferChunks;
  if (count > capacity)
    throw Error(what + ": " + std::to_string(count) + " elements exceed what this device can bind (" +
                std::to_string(capacity) + " in " + std::to_string(gpu::kMaxBufferChunks) + " buffers of at most " +
                std::to_string(maxRange) + " bytes)");
  return shift;
}

uint64_t maxChunkBytes(const VulkanContext& context) {
  const uint64_t device = context.properties().limits.maxStorageBufferRange;
  const char* text = std::getenv("VKTG_MAX_CHUNK_BYTES");
  if (!text || !*text) return device;
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (errno != 0 || *end != '\0' || text[0] == '-' || value < 16)
    throw Error("VKTG_MAX_CHUNK_BYTES: '" + std::string(text) + "' is not a whole number of bytes of at least 16");
  return std::min<uint64_t>(device, value);
}

ChunkedBuffer allocateChunked(const VulkanContext& context, size_t elementSize, size_t count, const std::string& name) {
  ChunkedBuffer out;
  out.shift = chunkShiftFor(elementSize, count, maxChunkBytes(context), name);
  size_t perChunk = size_t(1) << out.shift;
  size_t chunks = std::max<size_t>(1, (count + perChunk - 1) / perChunk);
  for (size_t c = 0; c < chunks; ++c) {
    size_t elements = std::min(perChunk, count - std::min(count, c * perChunk));
    out.chunks.emplace_back(context, std::max<size_t>(elements * elementSize, 16), MemoryKind::Device,
                            name + "[" + std::to_string(c) + "]");
  }
  return out;
}

bool fitsTexelView(const VulkanContext& context, uint64_t bytes) {
  return bytes / sizeof(glm::uvec4) <= context.properties().limits.maxTexelBufferElements;
}

bool fitsTexelView(const VulkanContext& context, const Buffer& buffer) { return fitsTexelView(context, buffer.size()); }

BufferView texelView(const VulkanContext& context, const Buffer& buffer, const std::string& name) {
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.handle();
  info.format = VK_FORMAT_R32G32B32A32_UINT;
  info.range = VK_WHOLE_SIZE;
  VkBufferView view;
  VKTG_VK_CHECK(vkCreateBufferView(context.device(), &info, nullptr, &view));
  context.setObjectName(VK_OBJECT_TYPE_BUFFER_VIEW, uint64_t(view), name);
  return BufferView(context.device(), view);
}

namespace {

// Whether the traversal loads the scene through texel buffers: by default on CPU devices (lavapipe
// traces 1.2-1.5x the rays per second with them, docs/benchmarks.md), never where a buffer takes
// several chunks or more texels than a view may hold.
bool useSceneTexels(const VulkanContext& context, const GpuScene& scene, std::optional<bool> forced) {
  if (!scene.triangles.single() || !scene.bvhNodes.single() || !fitsTexelView(context, scene.triangles.chunks[0]) ||
      !fitsTexelView(context, scene.bvhNodes.chunks[0]))
    return false;
  return forced.value_or(context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU);
}

}  // namespace

ChunkedBuffer uploadChunked(const VulkanContext& context, const void* data, size_t elementSize, size_t count,
                            const std::string& name) {
  ChunkedBuffer out = allocateChunked(context, elementSize, count, name);
  size_t perChunk = size_t(1) << out.shift;
  for (size_t c = 0; c < out.chunks.size(); ++c) {
    size_t first = c * perChunk;
    size_t elements = std::min(perChunk, count - std::min(count, first));
    out.chunks[c].upload(context, static_cast<const char*>(data) + first * elementSize, elements * elementSize);
  }
  return out;
}

GpuScene::GpuScene(const VulkanContext& context, const PreparedScene& prepared)
    : triangles(uploadChunked(context, prepared.triangles.data(), sizeof(gpu::GpuTriangle), prepared.triangles.size(),
                              "scene.triangles")),
      bvhNodes(uploadChunked(context, prepared.bvh.nodes.data(), sizeof(gpu::GpuBvhNode), prepared.bvh.nodes.size(),
                             "scene.bvhNodes")),
      triangleVerts(uploadArray(context, prepared.triangleVerts, "scene.triangleVerts")),
      vertices(uploadArray(context, prepared.vertices, "scene.vertices")),
      shapes(uploadArray(context, prepared.shapes, "scene.shapes")),
      materials(uploadArray(context, prepared.materials, "scene.materials")),
      lights(uploadArray(context, prepared.lights, "scene.lights")) {
  // Both variables are read on every device, so a bad value is an error wherever it is set, not
  // only on the devices whose choice it would change.
  const std::optional<bool> forcedTexels = forcedChoice("VKTG_SCENE_ACCESS", "texel", "storage");
  // The 4-wide BVH is wanted by default wherever the scene is read through texel views (CPU
  // devices, docs/benchmarks.md).
  const bool wideBvhWanted = forcedChoice("VKTG_BVH_WIDTH", "4", "2").value_or(true);
  if (useSceneTexels(context, *this, forcedTexels)) {
    triangleTexels = texelView(context, triangles.chunks[0], "scene.triangleTexels");
    bvhNodeTexels = texelView(context, bvhNodes.chunks[0], "scene.bvhNodeTexels");
  }
  // The wide nodes are read through a texel view only: without the scene's views it is not made.
  if (texels() && wideBvhWanted) {
    const std::vector<gpu::GpuWideBvhNode> wide = collapseBvh(prepared.bvh);
    if (!wide.empty() && fitsTexelView(context, wide.size() * sizeof(gpu::GpuWideBvhNode))) {
      wideBvhNodes = uploadArray(context, wide, "scene.wideBvhNodes");
      wideBvhTexels = texelView(context, wideBvhNodes, "scene.wideBvhTexels");
      bytes += wideBvhNodes.size();
    }
  }
  for (const ChunkedBuffer* chunked : {&triangles, &bvhNodes})
    for (const Buffer& b : chunked->chunks) bytes += b.size();
  for (const Buffer* b : {&triangleVerts, &vertices, &shapes, &materials, &lights}) bytes += b->size();
}

}  // namespace vktg
