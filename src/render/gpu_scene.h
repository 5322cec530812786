// A PreparedScene uploaded to device buffers. Arrays that may exceed maxStorageBufferRange
// (triangles, BVH nodes) are split into up to gpu::kMaxBufferChunks chunks.
#pragma once
#include <string>
#include <vector>

#include "vk/vk_resources.h"
#include "vktg/prepared_scene.h"

namespace vktg {

// One logical array split into power-of-two-sized chunks (element i is in chunk i >> shift).
struct ChunkedBuffer {
  std::vector<Buffer> chunks;
  uint32_t shift = 0;

  bool single() const { return chunks.size() <= 1; }
};

// Chooses the largest power-of-two chunk that fits `maxRange` bytes; throws vktg::Error naming
// `what` when even kMaxBufferChunks chunks cannot hold `count` elements.
uint32_t chunkShiftFor(size_t elementSize, size_t count, uint64_t maxRange, const std::string& what);
// The most bytes one chunk may hold on this device: maxStorageBufferRange, or less where the
// environment variable VKTG_MAX_CHUNK_BYTES asks for less (so tests split buffers on any device).
uint64_t maxChunkBytes(const VulkanContext& context);
// A view of `buffer` as R32G32B32A32_UINT texels (a uniform texel buffer), and whether one view can
// cover it (maxTexelBufferElements).
BufferView texelView(const VulkanContext& context, const Buffer& buffer, const std::string& name);
bool fitsTexelView(const VulkanContext& context, const Buffer& buffer);
bool fitsTexelView(const VulkanContext& context, uint64_t bytes);
ChunkedBuffer uploadChunked(const VulkanContext& context, const void* data, size_t elementSize, size_t count,
                            const std::string& name);
ChunkedBuffer allocateChunked(const VulkanContext& context, size_t elementSize, size_t count, const std::string& name);

struct GpuScene {
  GpuScene(const VulkanContext& context, const PreparedScene& prepared);

  ChunkedBuffer triangles;
  ChunkedBuffer bvhNodes;
  Buffer triangleVerts;
  Buffer vertices;
  Buffer shapes;
  Buffer materials;
  Buffer lights;
  // Views of triangles and BVH nodes for the traversal's loads (kSpecSceneTexels), made where they
  // measure faster: on CPU devices, where each holds one chunk and fits maxTexelBufferElements.
  // VKTG_SCENE_ACCESS=storage|texel overrides the device's choice (tests, benchmarks); renders
  // read path states and hits through texel views where the scene has them.
  BufferView triangleTexels, bvhNodeTexels;
  // The BVH collapsed to 4 children per node (collapseBvh), which the closest- and any-hit
  // traversals use where it is made (kSpecWideBvh): with the texel views, for a tree the layout
  // holds (refit_wide_bvh follows the binary tree's refit). VKTG_BVH_WIDTH=2|4 overrides the
  // choice (4 where it can be made).
  Buffer wideBvhNodes;
  BufferView wideBvhTexels;
  size_t bytes = 0;  // device memory held

  bool texels() const { return bool(bvhNodeTexels); }
  bool wideBvh() const { return bool(wideBvhTexels); }

  // Whether the chunked arrays hold one chunk each (kSpecSingleChunk, with the film's answer).
  bool singleChunk() const { return triangles.single() && bvhNodes.single(); }
};

}  // namespace vktg
