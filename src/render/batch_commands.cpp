#include "render/batch_commands.h"

#include "vktg/gpu/shared.h"

namespace vktg {

uint32_t workgroupsFor(uint64_t items) { return uint32_t((items + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize); }

TermPipelines termPipelines(PassPipelines& pipelines, const TermPasses& passes, RenderMode mode, const SpecValues& spec,
                            bool strategies, bool adjointImage, bool resolve) {
  TermPipelines p;
  p.passes = &passes;
  p.mode = mode;
  const std::string start = p.startName(), shade = p.shadeName(), shadow = p.shadowName(), finish = p.finishName();
  std::vector<SpecValues> startSpecs = {spec}, strategySpecs;
  if (strategies) {
    startSpecs.front()[gpu::kSpecEdgeStrategy] = gpu::kEdgeSortSamples;
    strategySpecs.assign(gpu::kEdgeStrategyCount, spec);
    for (uint32_t strategy = 0; strategy < gpu::kEdgeStrategyCount; ++strategy)
      strategySpecs[strategy][gpu::kSpecEdgeStrategy] = strategy;
  }
  // Forward renders end a batch in the film; adjoint ones in the adjoint's last step, then the film
  // where they return their image.
  const bool adjoint = mode == RenderMode::Adjoint;
  const std::string accumulate = adjoint ? (adjointImage ? "accumulate" : "") : finish == "accumulate" ? finish : "";
  const std::string splats = !adjoint && finish == "accumulate_splats" ? finish : "";
  std::vector<std::pair<std::string, SpecValues>> all;
  for (const SpecValues& s : startSpecs) all.push_back({start, s});
  for (const SpecValues& s : strategySpecs) all.push_back({start, s});
  if (passes.bounces) all.insert(all.end(), {{"intersect_closest", spec}, {shade, spec}});
  all.insert(all.end(), {{shadow, spec}, {"set_dispatch_args", spec}});
  for (const std::string& name : {adjoint ? finish : std::string(), accumulate, splats})
    if (!name.empty()) all.push_back({name, spec});
  if (resolve) all.push_back({"resolve", spec});
  pipelines.prepare(all);

  for (const SpecValues& s : startSpecs) p.start.push_back(pipelines.get(start, s));
  for (const SpecValues& s : strategySpecs) p.strategies.push_back(pipelines.get(start, s));
  if (passes.bounces) {
    p.intersect = pipelines.get("intersect_closest", spec);
    p.shade = pipelines.get(shade, spec);
  }
  p.shadow = pipelines.get(shadow, spec);
  p.setArgs = pipelines.get("set_dispatch_args", spec);
  if (adjoint && !finish.empty()) p.finish = pipelines.get(finish, spec);
  if (!accumulate.empty()) p.accumulate = pipelines.get(accumulate, spec);
  if (!splats.empty()) p.splats = pipelines.get(splats, spec);
  if (resolve) p.resolve = pipelines.get("resolve", spec);
  return p;
}

BatchCommands::BatchCommands(VkCommandBuffer cmd, VkPipelineLayout layout, PassProfiler& profiler,
                             const WavefrontBuffers& wave, const TermPipelines& pipelines)
    : m_cmd(cmd), m_layout(layout), m_profiler(profiler), m_wave(wave), m_pipelines(pipelines) {}

void BatchCommands::push(uint32_t x, uint32_t y, uint32_t z, uint32_t w) {
  gpu::PassPush push{glm::uvec4(x, y, z, w)};
  vkCmdPushConstants(m_cmd, m_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
}

void BatchCommands::dispatch(const char* name, VkPipeline pipeline, uint32_t groups) {
  m_profiler.begin(m_cmd, name);
  vkCmdBindPipeline(m_cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdDispatch(m_cmd, groups, 1, 1);
  m_profiler.end(m_cmd);
  computeBarrier(m_cmd);
}

void BatchCommands::dispatchIndirect(const char* name, VkPipeline pipeline, uint32_t argsRecord) {
  m_profiler.begin(m_cmd, name);
  vkCmdBindPipeline(m_cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdDispatchIndirect(m_cmd, m_wave.dispatchArgs.handle(), argsRecord * 3 * sizeof(uint32_t));
  m_profiler.end(m_cmd);
  computeBarrier(m_cmd);
}

void BatchCommands::zeroCounter(uint32_t counter) {
  vkCmdFillBuffer(m_cmd, m_wave.counters.handle(), counter * sizeof(uint32_t), sizeof(uint32_t), 0);
  computeBarrier(m_cmd);
}

void BatchCommands::clearBatchState(uint32_t batchSize) {
  vkCmdFillBuffer(m_cmd, m_wave.counters.handle(), 0, gpu::kCounterExtensionRays * sizeof(uint32_t), 0);
  vkCmdFillBuffer(m_cmd, m_wave.pathAccum.handle(), 0, VK_WHOLE_SIZE, 0);
  vkCmdFillBuffer(m_cmd, m_wave.rayQueues.handle(), 3ull * batchSize * sizeof(uint32_t), uint64_t(batchSize) * sizeof(uint32_t), 0);
  if (!m_pipelines.strategies.empty())
    vkCmdFillBuffer(m_cmd, m_wave.counters.handle(), gpu::kCounterEdgeQueues * sizeof(uint32_t),
                    gpu::kEdgeStrategyCount * sizeof(uint32_t), 0);
  computeBarrier(m_cmd);
}

void BatchCommands::startSamples(uint32_t first, uint32_t firstSample, uint32_t active) {
  push(first, firstSample, 0, active);
  for (VkPipeline pipeline : m_pipelines.start) dispatch(m_pipelines.startName(), pipeline, workgroupsFor(active));
  static constexpr const char* kStrategyPassNames[] = {"sample_edges_primary", "sample_edges_to_light",
                                                       "sample_edges_secondary"};
  for (uint32_t strategy = 0; strategy < m_pipelines.strategies.size(); ++strategy) {
    push(gpu::kCounterEdgeQueues + strategy, gpu::kArgsRays, gpu::kCounterCount, 0);
    dispatch("set_dispatch_args", m_pipelines.setArgs, 1);
    push(first, firstSample, 0, active);
    dispatchIndirect(kStrategyPassNames[strategy], m_pipelines.strategies[strategy], gpu::kArgsRays);
  }
}

void BatchCommands::bounce(uint32_t depth) {
  const uint32_t parity = depth & 1u;
  push(gpu::kCounterRays0 + parity, gpu::kArgsRays, gpu::kCounterExtensionRays, 0);
  dispatch("set_dispatch_args", m_pipelines.setArgs, 1);
  push(0, 0, depth, 0);
  if (!(m_pipelines.passes->firstHitKnown && depth == 0))
    dispatchIndirect("intersect_closest", m_pipelines.intersect, gpu::kArgsRays);
  zeroCounter(gpu::kCounterRays0 + (parity ^ 1u));
  dispatchIndirect(m_pipelines.shadeName(), m_pipelines.shade, gpu::kArgsRays);
  traceShadowRays();
}

void BatchCommands::traceShadowRays() {
  push(gpu::kCounterShadow, gpu::kArgsShadow, gpu::kCounterCount, 0);
  dispatch("set_dispatch_args", m_pipelines.setArgs, 1);
  dispatchIndirect(m_pipelines.shadowName(), m_pipelines.shadow, gpu::kArgsShadow);
  zeroCounter(gpu::kCounterShadow);
}

void BatchCommands::finishPaths(uint64_t slots) {
  push(0, 0, 0, uint32_t(slots));
  dispatch(m_pipelines.finishName(), m_pipelines.finish, workgroupsFor(slots));
}

void BatchCommands::accumulate(uint32_t firstLinear, uint32_t batchIndex, uint32_t active, uint64_t pixels,
                               uint64_t filmElements) {
  const uint64_t pathsPerPixel = (active + pixels - 1) / pixels;
  for (uint32_t round = 0; uint64_t(round) * gpu::kPathsPerRound < pathsPerPixel; ++round) {
    push(firstLinear, round, batchIndex, active);
    dispatch("accumulate", m_pipelines.accumulate, workgroupsFor(filmElements));
  }
}

void BatchCommands::accumulateSplats(uint32_t active, uint32_t layers, uint32_t lanes) {
  push(0, 0, 0, active);
  dispatch("accumulate_splats", m_pipelines.splats, workgroupsFor(uint64_t(active) * layers * lanes));
}

void BatchCommands::resolve(uint64_t filmElements) {
  push(0, 0, 0, uint32_t(filmElements));
  dispatch("resolve", m_pipelines.resolve, workgroupsFor(filmElements));
}

}  // namespace vktg
