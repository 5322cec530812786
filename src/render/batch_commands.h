// The commands of one batch of a render, a named call per stage: clear the batch's state, start
// its samples, each bounce of the per-depth loop, the shadow rays, and what ends the batch. Which
// pipelines run comes from the term's row of the pass table (pass_table.h), created by the renderer.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "render/pass_pipelines.h"
#include "render/pass_table.h"
#include "render/wavefront.h"
#include "vk/pass_profiler.h"
#include "vk/vk_resources.h"

namespace vktg {

// The pipelines of one render: its term's passes in its mode, with the pass labels the profile
// reports them under. VK_NULL_HANDLE where the term and mode have no such pass.
struct TermPipelines {
  const TermPasses* passes = nullptr;
  RenderMode mode = RenderMode::Primal;
  std::vector<VkPipeline> start;       // the first pass; with strategies, its sorting step
  std::vector<VkPipeline> strategies;  // each sampling strategy over the samples sorted to it
  VkPipeline intersect = VK_NULL_HANDLE, shade = VK_NULL_HANDLE, shadow = VK_NULL_HANDLE;
  VkPipeline setArgs = VK_NULL_HANDLE;
  VkPipeline finish = VK_NULL_HANDLE;      // the adjoint's last step (adjoint renders)
  VkPipeline accumulate = VK_NULL_HANDLE;  // per-pixel film accumulation
  VkPipeline splats = VK_NULL_HANDLE;      // splatted film accumulation
  VkPipeline resolve = VK_NULL_HANDLE;

  const char* startName() const { return passes->start[size_t(mode)]; }
  const char* shadeName() const { return passes->shade[size_t(mode)]; }
  const char* shadowName() const { return passes->shadow[size_t(mode)]; }
  const char* finishName() const { return passes->finish[size_t(mode)]; }
};

// Creates (together: in parallel on a GPU, where a driver that compiles at creation spends most of a
// short render's start-up) the pipelines of `passes` in `mode` with the specialisation `spec`:
// with `strategies`, the first pass's sorting step and one pipeline per sampling strategy; the
// film's accumulation for an adjoint render that returns its image (`adjointImage`); its resolve
// where the render has a film.
TermPipelines termPipelines(PassPipelines& pipelines, const TermPasses& passes, RenderMode mode, const SpecValues& spec,
                            bool strategies, bool adjointImage, bool resolve);

class BatchCommands {
 public:
  BatchCommands(VkCommandBuffer cmd, VkPipelineLayout layout, PassProfiler& profiler, const WavefrontBuffers& wave,
                const TermPipelines& pipelines);
  // What every batch starts from: the ray counters, the path accumulators, the shadow-slot masks
  // (trace_shadow_rays clears what it visits; a fresh batch starts clear) and the strategy queues.
  void clearBatchState(uint32_t batchSize);
  // The term's first pass over `active` samples from (first, firstSample), then each strategy's.
  void startSamples(uint32_t first, uint32_t firstSample, uint32_t active);
  // Depth `depth` of the per-depth loop: closest hits, shading, shadow rays.
  void bounce(uint32_t depth);
  void traceShadowRays();
  // The adjoint's last step over `slots` path slots.
  void finishPaths(uint64_t slots);
  // The film's accumulation of per-pixel paths (`pixels` pixels, `filmElements` elements): a
  // round per kPathsPerRound paths per pixel.
  void accumulate(uint32_t firstLinear, uint32_t batchIndex, uint32_t active, uint64_t pixels, uint64_t filmElements);
  // The film's accumulation of splatted samples.
  void accumulateSplats(uint32_t active, uint32_t layers, uint32_t lanes);
  void resolve(uint64_t filmElements);

 private:
  void push(uint32_t x, uint32_t y, uint32_t z, uint32_t w);
  void dispatch(const char* name, VkPipeline pipeline, uint32_t groups);
  void dispatchIndirect(const char* name, VkPipeline pipeline, uint32_t argsRecord);
  void zeroCounter(uint32_t counter);

  VkCommandBuffer m_cmd;
  VkPipelineLayout m_layout;
  PassProfiler& m_profiler;
  const WavefrontBuffers& m_wave;
  const TermPipelines& m_pipelines;
};

// Workgroups of kWorkgroupSize invocations covering `items`.
uint32_t workgroupsFor(uint64_t items);

}  // namespace vktg
