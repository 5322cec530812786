#include "host/renderer.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "host/frame_uniforms.h"
#include "host/interrupt.h"
#include "host/memory_preflight.h"
#include "host/pass_pipelines.h"
#include "host/pass_profiler.h"
#include "host/wavefront.h"
#include "vktg/error.h"
#include "vktg/silhouette_edges.h"

namespace vktg {
namespace {

void pushArgs(VkCommandBuffer cmd, VkPipelineLayout layout, uint32_t x, uint32_t y, uint32_t z, uint32_t w) {
  gpu::PassPush push{glm::uvec4(x, y, z, w)};
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
}

uint32_t groupsFor(uint64_t items) { return uint32_t((items + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize); }

// What each derivative lane differentiates, in GPU terms.
std::vector<gpu::GpuLane> laneTable(const std::vector<ParameterBinding>& bindings, const PreparedScene& prepared,
                                    const Scene& scene) {
  uint32_t firstPointLight = uint32_t(prepared.lights.size() - scene.pointLights.size());
  std::vector<gpu::GpuLane> lanes;
  for (const ParameterBinding& b : bindings) {
    gpu::GpuLane lane{};
    switch (b.kind) {
      case ParameterKind::Translate:
      case ParameterKind::Rotate:
      case ParameterKind::Displace: lane.info = glm::uvec4(gpu::kLaneGeometry, 0, 0, 0); break;
      case ParameterKind::LightPosition:
        lane.info = glm::uvec4(gpu::kLaneGeometry, firstPointLight + b.target, 1, 0);
        lane.lightVelocity = glm::vec4(b.lightVelocity, 0.0f);
        break;
      case ParameterKind::Emission: lane.info = glm::uvec4(gpu::kLaneEmission, b.target, 0, 0); break;
      case ParameterKind::Intensity: lane.info = glm::uvec4(gpu::kLaneIntensity, firstPointLight + b.target, 0, 0); break;
      case ParameterKind::Albedo: lane.info = glm::uvec4(gpu::kLaneAlbedo, b.target, 0, 0); break;
      case ParameterKind::Roughness: lane.info = glm::uvec4(gpu::kLaneRoughness, b.target, 0, 0); break;
      case ParameterKind::Ior: lane.info = glm::uvec4(gpu::kLaneIor, b.target, 0, 0); break;
      case ParameterKind::GateCenter: lane.info = glm::uvec4(gpu::kLaneGateCenter, 0, 0, 0); break;
    }
    lanes.push_back(lane);
  }
  return lanes;
}

// Vertices any lane moves: the edge pass puts extra selection mass on their edges.
std::vector<bool> movingVertices(const std::vector<ParameterBinding>& bindings, size_t vertexCount) {
  std::vector<bool> moving(vertexCount, false);
  for (const ParameterBinding& b : bindings)
    for (size_t v = 0; v < b.vertexVelocity.size() && v < vertexCount; ++v)
      if (b.vertexVelocity[v] != glm::vec3(0.0f)) moving[v] = true;
  return moving;
}

}  // namespace

struct Renderer::Impl {
  explicit Impl(VulkanContext& c)
      : context(c), pipelines(c, kShaderRegistry, defaultPipelineCacheFile(c)),
        dummy(c, 256, MemoryKind::Device, "dummy") {}
  VulkanContext& context;
  PassPipelines pipelines;
  Buffer dummy;
};

Renderer::Renderer(VulkanContext& context) : m_impl(std::make_unique<Impl>(context)) {}
Renderer::~Renderer() = default;

RenderResult Renderer::render(const Scene& scene, const RenderOptions& options) {
  VulkanContext& context = m_impl->context;
  PassPipelines& pipelines = m_impl->pipelines;
  RenderResult result;
  PreparedScene prepared = prepareScene(scene);
  result.plan = planRender(scene, prepared, options.nee);
  const RenderPlan& plan = result.plan;
  GpuScene gpuScene(context, prepared);

  const uint32_t layers = plan.layers;
  const uint32_t lanes = uint32_t(options.derivativeLanes.size());
  const uint32_t channels = 1 + lanes;
  if (lanes > kMaxDerivativeLanes) throw Error("internal: more derivative lanes than kMaxDerivativeLanes");
  const uint32_t width = scene.camera.type == CameraType::PointSensor ? 1 : scene.camera.width;
  const uint32_t height = scene.camera.type == CameraType::PointSensor ? 1 : scene.camera.height;
  const uint64_t pixels = uint64_t(width) * height;
  // The edge term counts edge samples (each owns two path slots); the others count paths.
  const uint64_t totalPaths = pixels * scene.render.spp;
  const bool edges = options.edges, fromCamera = options.pathLengthFromCamera;
  // Splatted samples (edge term, path-length boundary from the camera) own two path slots each and
  // land in the pixels their camera connections reach.
  const bool splat = edges || fromCamera;
  const uint32_t slotsPerSample = splat ? 2 : 1;
  if (edges && (lanes == 0 || options.pathLengthBoundary))
    throw Error("internal: the edge term needs derivative lanes and excludes the path-length-boundary term");
  if (fromCamera && !options.pathLengthBoundary)
    throw Error("internal: path-length-boundary connections from the camera belong to that term");
  if (splat && totalPaths >= (uint64_t(1) << 32))
    throw Error(std::string(edges ? "--spp-edge: " : "--spp-boundary: ") + std::to_string(totalPaths) +
                " splatted samples are too many for one render");
  if (pixels * scene.render.spp > (uint64_t(1) << 32) * 8)
    throw Error("render: " + std::to_string(totalPaths) + " paths are too many for one render");

  const uint64_t filmElements = pixels * layers * channels;
  // kFilmFloatsPerElement floats per element (shift, compensated sums; see shared.h).
  const uint64_t filmFloats = gpu::kFilmFloatsPerElement * filmElements;
  uint64_t filmBytes = filmFloats * sizeof(float);
  const std::vector<gpu::GpuEdge> edgeList =
      edges ? silhouetteEdges(prepared, movingVertices(options.derivativeLanes, prepared.vertices.size()))
            : std::vector<gpu::GpuEdge>{};
  RenderMemory need;
  need.film = filmBytes;
  need.scene = gpuScene.bytes + edgeList.size() * sizeof(gpu::GpuEdge);
  need.smallestBatch = wavefrontBytesPerPath(layers, lanes) * gpu::kWorkgroupSize;
  need.filmShape = std::to_string(width) + " x " + std::to_string(height) + " pixels x " + std::to_string(layers) +
                   " layers x " + std::to_string(channels) + " channels";
  const uint64_t budget = checkRenderMemory(context, need, options.memoryBudget);
  ChunkedBuffer film = allocateChunked(context, sizeof(float), filmFloats, "film");
  Buffer edgeBuffer(context, std::max<size_t>(16, edgeList.size() * sizeof(gpu::GpuEdge)), MemoryKind::Device, "scene.edges");
  edgeBuffer.upload(context, edgeList.data(), edgeList.size() * sizeof(gpu::GpuEdge));
  const uint32_t batchSize =
      batchSizeFor(budget - filmBytes - gpuScene.bytes - edgeBuffer.size(), layers, lanes,
                   context.properties().limits.maxStorageBufferRange, totalPaths * slotsPerSample,
                   context.properties().limits.maxComputeWorkGroupCount[0]);
  const uint32_t samplesPerBatch = batchSize / slotsPerSample;
  WavefrontBuffers wave(context, batchSize, layers, lanes);
  // Derivative inputs: per-lane vertex velocities and what each lane differentiates.
  std::vector<glm::vec4> velocities(std::max<size_t>(1, size_t(lanes) * prepared.vertices.size()), glm::vec4(0.0f));
  for (uint32_t k = 0; k < lanes; ++k)
    for (size_t v = 0; v < options.derivativeLanes[k].vertexVelocity.size(); ++v)
      velocities[k * prepared.vertices.size() + v] = glm::vec4(options.derivativeLanes[k].vertexVelocity[v], 0.0f);
  Buffer velocityBuffer(context, velocities.size() * sizeof(glm::vec4), MemoryKind::Device, "derivative.vertexVelocity");
  velocityBuffer.upload(context, velocities.data(), velocities.size() * sizeof(glm::vec4));
  std::vector<gpu::GpuLane> laneInfo = laneTable(options.derivativeLanes, prepared, scene);
  if (laneInfo.empty()) laneInfo.emplace_back();
  Buffer laneBuffer(context, laneInfo.size() * sizeof(gpu::GpuLane), MemoryKind::Device, "derivative.lanes");
  laneBuffer.upload(context, laneInfo.data(), laneInfo.size() * sizeof(gpu::GpuLane));

  gpu::FrameUniforms frame = sceneFrameUniforms(scene, prepared, gpuScene);
  setGateUniforms(frame, scene.gate, options.gateCutoff);
  frame.gateInfo.z = plan.nee == NeeMode::Ellipsoidal ? gpu::kNeeEllipsoidal
                     : plan.nee == NeeMode::Mis     ? gpu::kNeeMis
                                                    : gpu::kNeeStandard;
  frame.pathInfo = glm::uvec4(scene.render.rouletteDepth, plan.firstEllipsoidVertex, channels, batchSize);
  frame.chunkShift.z = film.shift;
  frame.edgeInfo = glm::uvec4(uint32_t(edgeList.size()), edges ? uint32_t(totalPaths) : 0u, 0, 0);
  // resolve divides by the samples every pixel's sums saw: a splatted sample counts in every pixel.
  if (splat) frame.image.z = uint32_t(totalPaths);
  Buffer frameBuffer(context, sizeof frame, MemoryKind::Device, "frame");
  frameBuffer.upload(context, &frame, sizeof frame);

  BindingTable table;
  table.setScene(gpuScene);
  table.set(gpu::kBindingFrame, frameBuffer);
  table.set(gpu::kBindingPaths, wave.paths);
  table.set(gpu::kBindingHits, wave.hits);
  table.set(gpu::kBindingRayQueues, wave.rayQueues);
  table.set(gpu::kBindingShadowQueue, wave.shadowQueue);
  table.set(gpu::kBindingCounters, wave.counters);
  table.set(gpu::kBindingDispatchArgs, wave.dispatchArgs);
  table.set(gpu::kBindingPathAccum, wave.pathAccum);
  table.setChunks(gpu::kBindingFilm, film);
  table.set(gpu::kBindingVertexVelocity, velocityBuffer);
  table.set(gpu::kBindingLanes, laneBuffer);
  table.set(gpu::kBindingPathDerivs, wave.pathDerivs);
  table.set(gpu::kBindingShadowDerivs, wave.shadowDerivs);
  table.set(gpu::kBindingEdges, edgeBuffer);
  DescriptorSet set(context, pipelines.setLayout(), table, m_impl->dummy);

  SpecValues spec{};
  spec[gpu::kSpecMaterialMask] = prepared.materialMask;
  spec[gpu::kSpecNeeMode] = frame.gateInfo.z;
  spec[gpu::kSpecGateType] = uint32_t(scene.gate.type);
  spec[gpu::kSpecCameraType] = uint32_t(scene.camera.type);
  spec[gpu::kSpecLightMask] = prepared.lightMask;
  spec[gpu::kSpecLanes] = std::max(lanes, 1u);
  spec[gpu::kSpecTerm] = options.pathLengthBoundary ? gpu::kTermPathLength : gpu::kTermInterior;
  spec[gpu::kSpecAntithetic] = options.antithetic ? 1u : 0u;
  if (options.pathLengthBoundary && (lanes == 0 || !scene.gate.hasJumps()))
    throw Error("internal: the path-length-boundary term needs derivative lanes and a gate with jumps");
  // The derivative variants carry the lanes; passes without derivative work are shared. The edge
  // term's light sides are plain paths (their lanes are factors sample_edges set).
  const std::string variant = lanes > 0 && !edges ? "_d" : "";
  const std::string shadeName = "shade" + variant, shadowName = "trace_shadow_rays" + variant;
  const std::string generateName = edges        ? "sample_edges"
                                   : fromCamera ? "connect_camera_boundary"
                                                : "generate_camera_rays" + variant;
  const std::string accumulateName = splat ? "accumulate_splats" : "accumulate";
  VkPipeline generate = pipelines.get(generateName, spec);
  VkPipeline intersect = pipelines.get("intersect_closest", spec);
  VkPipeline shade = pipelines.get(shadeName, spec);
  VkPipeline shadow = pipelines.get(shadowName, spec);
  VkPipeline setArgs = pipelines.get("set_dispatch_args", spec);
  VkPipeline accumulate = pipelines.get(accumulateName, spec);
  VkPipeline resolve = pipelines.get("resolve", spec);
  VkPipelineLayout layout = pipelines.layout();
  VkDescriptorSet ds = set.get();

  const uint32_t maxDepth = scene.render.maxDepth;
  PassProfiler profiler(context, 8 + 6 * maxDepth);
  CommandBuffer cmdBuffer(context, "render batch");
  VkCommandBuffer cmd = cmdBuffer.get();

  auto dispatch = [&](const char* name, VkPipeline pipeline, uint32_t groups) {
    profiler.begin(cmd, name);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdDispatch(cmd, groups, 1, 1);
    profiler.end(cmd);
    computeBarrier(cmd);
  };
  auto dispatchIndirect = [&](const char* name, VkPipeline pipeline, uint32_t argsRecord) {
    profiler.begin(cmd, name);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdDispatchIndirect(cmd, wave.dispatchArgs.handle(), argsRecord * 3 * sizeof(uint32_t));
    profiler.end(cmd);
    computeBarrier(cmd);
  };
  auto zeroCounter = [&](uint32_t counter) {
    vkCmdFillBuffer(cmd, wave.counters.handle(), counter * sizeof(uint32_t), sizeof(uint32_t), 0);
    computeBarrier(cmd);
  };

  // Statistics counters accumulate over all batches: zero them once.
  {
    CommandBuffer init(context, "render init");
    init.begin();
    vkCmdFillBuffer(init.get(), wave.counters.handle(), 0, VK_WHOLE_SIZE, 0);
    for (const Buffer& b : film.chunks) vkCmdFillBuffer(init.get(), b.handle(), 0, VK_WHOLE_SIZE, 0);
    init.end();
    context.submitAndWait(init.get());
  }

  auto start = std::chrono::steady_clock::now();
  uint64_t done = 0;
  while (done < totalPaths) {
    uint32_t active = uint32_t(std::min<uint64_t>(samplesPerBatch, totalPaths - done));
    uint32_t firstSample = uint32_t(done / pixels);
    uint32_t firstLinear = uint32_t(done - uint64_t(firstSample) * pixels);
    cmdBuffer.begin();
    profiler.reset(cmd);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &ds, 0, nullptr);
    vkCmdFillBuffer(cmd, wave.counters.handle(), 0, gpu::kCounterExtensionRays * sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, wave.pathAccum.handle(), 0, VK_WHOLE_SIZE, 0);
    computeBarrier(cmd);
    pushArgs(cmd, layout, splat ? uint32_t(done) : firstLinear, firstSample, 0, active);
    dispatch(generateName.c_str(), generate, groupsFor(active));
    auto traceShadowRays = [&] {
      pushArgs(cmd, layout, gpu::kCounterShadow, gpu::kArgsShadow, gpu::kCounterShadowRays, 0);
      dispatch("set_dispatch_args", setArgs, 1);
      dispatchIndirect(shadowName.c_str(), shadow, gpu::kArgsShadow);
      zeroCounter(gpu::kCounterShadow);
    };
    // connect_camera_boundary queues complete connections: no rays to extend.
    if (fromCamera) traceShadowRays();
    for (uint32_t depth = 0; depth < (fromCamera ? 0 : maxDepth); ++depth) {
      uint32_t parity = depth & 1u;
      pushArgs(cmd, layout, gpu::kCounterRays0 + parity, gpu::kArgsRays, gpu::kCounterExtensionRays, 0);
      dispatch("set_dispatch_args", setArgs, 1);
      pushArgs(cmd, layout, 0, 0, depth, 0);
      // sample_edges already found the hit at the end of every boundary segment.
      if (!(edges && depth == 0)) dispatchIndirect("intersect_closest", intersect, gpu::kArgsRays);
      zeroCounter(gpu::kCounterRays0 + (parity ^ 1u));
      dispatchIndirect(shadeName.c_str(), shade, gpu::kArgsRays);
      traceShadowRays();
    }
    if (splat) {
      pushArgs(cmd, layout, 0, 0, 0, active);
      dispatch("accumulate_splats", accumulate, groupsFor(uint64_t(active) * layers * lanes));
    } else {
      uint64_t pathsPerPixel = (active + pixels - 1) / pixels;
      for (uint32_t round = 0; uint64_t(round) * gpu::kPathsPerRound < pathsPerPixel; ++round) {
        pushArgs(cmd, layout, firstLinear, round, result.stats.batches, active);
        dispatch("accumulate", accumulate, groupsFor(filmElements));
      }
    }
    cmdBuffer.end();
    context.submitAndWait(cmd);
    profiler.collect();
    done += active;
    result.stats.batches++;
    if (options.progress) options.progress(double(done) / double(totalPaths));
    throwIfInterrupted();
  }
  {
    cmdBuffer.begin();
    profiler.reset(cmd);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &ds, 0, nullptr);
    pushArgs(cmd, layout, 0, 0, 0, uint32_t(filmElements));
    dispatch("resolve", resolve, groupsFor(filmElements));
    cmdBuffer.end();
    context.submitAndWait(cmd);
    profiler.collect();
  }
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<uint32_t> counters(gpu::kCounterCount);
  wave.counters.download(context, counters.data(), counters.size() * sizeof(uint32_t));
  RenderStats& stats = result.stats;
  stats.paths = totalPaths;
  stats.extensionRays = counters[gpu::kCounterExtensionRays];
  stats.shadowRays = counters[gpu::kCounterShadowRays];
  stats.endedByGate = counters[gpu::kCounterEndedByGate];
  stats.endedByRoulette = counters[gpu::kCounterEndedByRoulette];
  stats.endedByDepth = counters[gpu::kCounterEndedByDepth];
  stats.nonFinite = counters[gpu::kCounterNonFinite];
  stats.ellipsoidQueries = counters[gpu::kCounterEllipsoidQueries];
  stats.ellipsoidEmpty = counters[gpu::kCounterEllipsoidEmpty];
  stats.edgeSilhouettes = counters[gpu::kCounterEdgeSilhouettes];
  stats.edgeConnected = counters[gpu::kCounterEdgeConnected];
  stats.silhouetteEdges = edgeList.size();
  stats.batchSize = batchSize;
  stats.deviceBytes = gpuScene.bytes + wave.bytes() + filmBytes;
  result.passMilliseconds = profiler.millisecondsPerPass();

  std::vector<float> resolved(filmFloats), mean(filmElements), variance(filmElements);
  size_t perChunk = size_t(1) << film.shift;
  for (size_t c = 0; c < film.chunks.size(); ++c) {
    size_t first = c * perChunk;
    size_t count = std::min<size_t>(perChunk, filmFloats - first);
    film.chunks[c].download(context, resolved.data() + first, count * sizeof(float));
  }
  for (size_t i = 0; i < filmElements; ++i) {
    mean[i] = resolved[gpu::kFilmFloatsPerElement * i];
    variance[i] = resolved[gpu::kFilmFloatsPerElement * i + 1];
  }
  for (ImageSet* set : {&result.mean, &result.variance}) {
    set->width = width;
    set->height = height;
  }
  // Film element (channel * layers + layer) * pixels + pixel: channel 0 the image, then the lanes.
  auto layerOf = [&](const std::vector<float>& data, uint32_t channel, uint32_t layer) {
    auto first = data.begin() + (uint64_t(channel) * layers + layer) * pixels;
    return std::vector<float>(first, first + pixels);
  };
  result.derivatives.resize(lanes);
  result.derivativeVariances.resize(lanes);
  for (uint32_t c = 0; c < channels; ++c) {
    ImageSet& m = c == 0 ? result.mean : result.derivatives[c - 1];
    ImageSet& v = c == 0 ? result.variance : result.derivativeVariances[c - 1];
    m.width = v.width = width;
    m.height = v.height = height;
    for (uint32_t k = 0; k < layers; ++k) {
      std::string name = scene.gate.layerName(k);
      m.layers.push_back({name, layerOf(mean, c, k)});
      v.layers.push_back({name, layerOf(variance, c, k)});
    }
  }
  return result;
}

}  // namespace vktg
