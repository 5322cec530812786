#include "render/renderer.h"

#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "render/batch_commands.h"
#include "render/frame_uniforms.h"
#include "render/interrupt.h"
#include "render/memory_preflight.h"
#include "render/pass_pipelines.h"
#include "render/wavefront.h"
#include "scene/seeds.h"
#include "vk/forced_choice.h"
#include "vk/memory_arena.h"
#include "vk/pass_profiler.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// What each derivative lane differentiates, in GPU terms.
std::vector<gpu::GpuLane> laneTable(const std::vector<ParameterBinding>& bindings, uint32_t firstPointLight) {
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

// Vertices any lane moves (the edge pass puts extra selection mass on their edges), or only those a
// displacement moves (`deformingOnly`: their flat creases can fold).
std::vector<bool> movingVertices(const std::vector<ParameterBinding>& bindings, size_t vertexCount, bool deformingOnly) {
  std::vector<bool> moving(vertexCount, false);
  for (const ParameterBinding& b : bindings) {
    if (deformingOnly && b.kind != ParameterKind::Displace) continue;
    for (size_t v = 0; v < b.vertexVelocity.size() && v < vertexCount; ++v)
      if (b.vertexVelocity[v] != glm::vec3(0.0f)) moving[v] = true;
  }
  return moving;
}

template <class T>
Buffer uploaded(const VulkanContext& context, const std::vector<T>& data, const std::string& name) {
  Buffer buffer(context, std::max<size_t>(16, data.size() * sizeof(T)), MemoryKind::Device, name);
  buffer.upload(context, data.data(), data.size() * sizeof(T));
  return buffer;
}

// The per-path buffers a render of one kind and size needs; kept between renders of the same kind.
struct FrameResources {
  struct Key {
    uint32_t batchSize = 0, layers = 0, lanes = 0, tapeVertices = 0;
    bool shadowAdjoint = false, edgeRecords = false;
    bool operator==(const Key&) const = default;
  };
  // The buffers are bound into `arena`, whose earlier buffers must be gone (Impl::frameResources).
  FrameResources(const VulkanContext& context, const Key& k, MemoryArena& arena)
      : key(k), wave(context, k.batchSize, k.layers, k.lanes),
        tape(context, std::max<uint64_t>(16, uint64_t(k.batchSize) * k.tapeVertices * sizeof(gpu::TapeVertex)),
             MemoryKind::Device, "adjoint.tape", Binding::Arena),
        shadowAdjoint(context,
                      k.shadowAdjoint ? uint64_t(k.batchSize) * gpu::kShadowRaysPerPath * sizeof(gpu::ShadowAdjoint) : 16,
                      MemoryKind::Device, "adjoint.shadow", Binding::Arena),
        edgeRecords(context, k.edgeRecords ? uint64_t(k.batchSize) * sizeof(gpu::EdgeRecord) : 16, MemoryKind::Device,
                    "edges.records", Binding::Arena) {
    std::vector<Buffer*> buffers = wave.all();
    buffers.insert(buffers.end(), {&tape, &shadowAdjoint, &edgeRecords});
    arena.bind(buffers);
  }
  uint64_t bytes() const { return wave.bytes() + tape.size() + shadowAdjoint.size() + edgeRecords.size(); }
  Key key;
  WavefrontBuffers wave;
  Buffer tape, shadowAdjoint, edgeRecords;
};

}  // namespace

struct Renderer::Impl {
  explicit Impl(VulkanContext& c)
      : context(c), pipelines(PassPipelines::shared(c, kShaderRegistry, defaultPipelineCacheFile(c))),
        dummy(c, 256, MemoryKind::Device, "dummy"), frameMemory(c, "frame state") {}
  VulkanContext& context;
  std::shared_ptr<PassPipelines> pipelines;
  Buffer dummy;
  MemoryArena frameMemory;                // declared before `frame`, which it outlives
  std::unique_ptr<FrameResources> frame;
  std::optional<ChunkedBuffer> film;
  uint64_t filmFloats = 0;
  // Kept between renders (an optimisation renders every iteration), grow-only: the frame block,
  // which the first batch's commands write, and where a film or the counters are copied for the
  // host when it cannot read them directly, by the last batch's commands.
  Buffer frameBlock, filmReadback, countersReadback;

  FrameResources& frameResources(const FrameResources::Key& key) {
    if (!frame || !(frame->key == key)) {
      frame.reset();  // the old buffers go before the new ones alias their memory
      frame = std::make_unique<FrameResources>(context, key, frameMemory);
    }
    return *frame;
  }
  ChunkedBuffer& filmFor(uint64_t floats) {
    if (!film || filmFloats != floats) {
      film.reset();
      film = allocateChunked(context, sizeof(float), floats, "film");
      filmFloats = floats;
    }
    return *film;
  }
};

Renderer::Renderer(VulkanContext& context) : m_impl(std::make_unique<Impl>(context)) {}
Renderer::~Renderer() = default;
VulkanContext& Renderer::context() const { return m_impl->context; }

RenderResult Renderer::render(const Scene& scene, const RenderOptions& options) {
  DeviceScene deviceScene(m_impl->context, scene);
  return render(deviceScene, RenderSetup::of(scene), options);
}

RenderResult Renderer::render(DeviceScene& deviceScene, const RenderSetup& setup, const RenderOptions& options) {
  return renderViews(deviceScene, setup, nullptr, options);
}

RenderResult Renderer::render(DeviceScene& deviceScene, const RenderSetup& setup, const std::vector<RenderView>& views,
                              const RenderOptions& options) {
  if (views.empty()) throw Error("internal: a render of several views needs at least one");
  return renderViews(deviceScene, setup, &views, options);
}

std::vector<ImageSet> splitViews(const ImageSet& stacked, size_t views) {
  if (views == 0 || stacked.height % views != 0) throw Error("internal: an image of views splits into equal parts");
  const uint32_t height = stacked.height / uint32_t(views);
  const size_t pixels = size_t(stacked.width) * height;
  std::vector<ImageSet> out(views);
  for (size_t v = 0; v < views; ++v) {
    out[v].width = stacked.width;
    out[v].height = height;
    for (const ImageLayer& layer : stacked.layers) {
      auto first = layer.pixels.begin() + ptrdiff_t(v * pixels);
      out[v].layers.push_back({layer.name, std::vector<float>(first, first + ptrdiff_t(pixels))});
    }
  }
  return out;
}

namespace {

// The frame block's view records (lib/view.glsl): per view its camera as FrameUniforms holds one,
// its seed, and every point light where the view places it.
std::vector<glm::vec4> viewRecords(const std::vector<RenderView>& views, const RenderSetup& setup,
                                   const DeviceScene& scene, const GpuScene& gpuScene, uint32_t& stride) {
  const size_t pointLights = scene.scene().pointLights.size();
  stride = uint32_t(4 + pointLights);
  std::vector<glm::vec4> records;
  records.reserve(views.size() * stride);
  for (const RenderView& view : views) {
    if (view.camera.type != setup.camera.type || imagePixels(view.camera) != imagePixels(setup.camera))
      throw Error("internal: the views of one render share the camera type and image size");
    const gpu::FrameUniforms f = sceneFrameUniforms(view.camera, setup.settings, scene.prepared(), gpuScene);
    records.push_back(glm::vec4(glm::vec3(f.cameraPosition), std::bit_cast<float>(view.seed)));
    records.insert(records.end(), {glm::vec4(glm::vec3(f.cameraForward), view.pathOffset), f.cameraRight, f.cameraUp});
    for (const glm::vec3& light : scene.pointLightsFor(view.lightPositions)) records.push_back(glm::vec4(light, 0.0f));
  }
  return records;
}

}  // namespace

RenderResult Renderer::renderViews(DeviceScene& deviceScene, const RenderSetup& setup,
                                   const std::vector<RenderView>* views, const RenderOptions& options) {
  VulkanContext& context = m_impl->context;
  PassPipelines& pipelines = *m_impl->pipelines;
  const PreparedScene& prepared = deviceScene.prepared();
  const GpuScene& gpuScene = deviceScene.gpu();
  RenderResult result;
  result.plan = planRender(setup, prepared, options.nee, options.ellipsoidSelection, options.neeNotes);
  const RenderPlan& plan = result.plan;
  const RenderSettings& settings = setup.settings;

  const AdjointTarget* adjoint = options.adjoint;
  const uint32_t layers = plan.layers;
  const uint32_t lanes = adjoint ? 0u : uint32_t(options.derivativeLanes.size());
  const uint32_t channels = 1 + lanes;
  if (lanes > kMaxDerivativeLanes) throw Error("internal: more derivative lanes than kMaxDerivativeLanes");
  if (adjoint && !options.derivativeLanes.empty()) throw Error("internal: an adjoint render has no lanes");
  if (adjoint && (!adjoint->image || !adjoint->gradient || !deviceScene.model()))
    throw Error("internal: an adjoint render needs an adjoint image, accumulators and a parameter model");
  const RenderMode mode = adjoint ? RenderMode::Adjoint : lanes > 0 ? RenderMode::Forward : RenderMode::Primal;
  const TermPasses& term = termPasses(options.term);
  if (!term.has(mode))
    throw Error(std::string("internal: the ") + termName(term.term) + " term has no " + renderModeName(mode) + " render");
  if (term.needsJumps && !setup.gate.hasJumps())
    throw Error(std::string("internal: the ") + termName(term.term) + " term needs a gate with jumps");
  const bool adjointImage = adjoint && adjoint->renderImage;
  if (adjointImage && (options.term != Term::Interior || options.samplesPerPixel > 0))
    throw Error("internal: only the interior term's adjoint render, at whole samples per pixel, renders its image");
  // Several views stack their images: `height` counts the rows of all of them.
  const uint32_t viewCount = views ? uint32_t(views->size()) : 1u;
  const uint32_t width = imagePixels(setup.camera).x, viewHeight = imagePixels(setup.camera).y;
  if (uint64_t(viewHeight) * viewCount >= (uint64_t(1) << 31)) throw Error("render: too many views for one render");
  const uint32_t height = viewHeight * viewCount;
  const uint64_t pixels = uint64_t(width) * height;
  const bool edges = options.term == Term::Edge;
  // Splatted samples (edge term, path-length boundary from the camera) own two path slots each and
  // land in the pixels their camera connections reach.
  const bool splat = term.splat;
  // The edge term counts edge samples (each owns two path slots); the others count paths.
  uint64_t totalPaths = pixels * settings.spp;
  if (options.samplesPerPixel > 0) {
    if (!splat && !adjoint) throw Error("internal: a fractional sample count needs a splatted or an adjoint render");
    if (!(options.samplesPerPixel * double(pixels) < 0x1p40)) throw Error("render: too many samples for one render");
    // Splatted samples are counted per view: as many in each.
    const uint64_t unit = splat ? viewCount : 1, units = pixels / unit;
    totalPaths = unit * std::max<uint64_t>(1, uint64_t(std::llround(options.samplesPerPixel * double(units))));
  }
  // Per-pixel paths fewer than (or not a multiple of) the pixels start from a pixel the seed draws,
  // so that every pixel gets totalPaths / pixels of them on average.
  const uint64_t firstPixel = !splat && totalPaths % pixels != 0 ? derivedSeed(settings.seed) % pixels : 0;
  const uint32_t slotsPerSample = splat ? 2 : 1;
  if (splat && totalPaths >= (uint64_t(1) << 32))
    throw Error(std::string(term.sampleOption) + ": " + std::to_string(totalPaths) +
                " splatted samples are too many for one render");
  // The first batch zeroes what the render accumulates into and the last copies it out.
  if (totalPaths == 0) throw Error("internal: a render needs at least one sample");
  if (totalPaths > (uint64_t(1) << 32) * 8)
    throw Error("render: " + std::to_string(totalPaths) + " paths are too many for one render");

  // An adjoint render produces no image unless asked: its film stays empty.
  const uint64_t filmElements = adjoint && !adjointImage ? 0 : pixels * layers * channels;
  // kFilmFloatsPerElement floats per element (shift, compensated sums; see shared.h).
  const uint64_t filmFloats = std::max<uint64_t>(gpu::kFilmFloatsPerElement, gpu::kFilmFloatsPerElement * filmElements);
  const uint64_t filmBytes = filmFloats * sizeof(float);
  const Buffer* edgeBuffer = nullptr;
  if (edges) {
    const size_t vertexCount = prepared.vertices.size();
    if (adjoint) {
      edgeBuffer = &deviceScene.edges(deviceScene.model()->movingVertices(), deviceScene.model()->deformingVertices());
    } else {
      edgeBuffer = &deviceScene.edges(movingVertices(options.derivativeLanes, vertexCount, false),
                                      movingVertices(options.derivativeLanes, vertexCount, true));
    }
  }
  const uint32_t edgeCount = edges ? deviceScene.edgeCount() : 0u;

  // Per-path state beyond the wavefront: the adjoint's tape and connection records, edge records.
  FrameResources::Key key;
  key.layers = layers;
  key.lanes = lanes;
  key.tapeVertices = adjoint && !splat ? settings.maxDepth + 1 : 0;
  key.shadowAdjoint = adjoint && !edges;
  key.edgeRecords = edges;
  ExtraPathState extra;
  extra.bytes = uint64_t(key.tapeVertices) * sizeof(gpu::TapeVertex) +
                (key.shadowAdjoint ? gpu::kShadowRaysPerPath * sizeof(gpu::ShadowAdjoint) : 0) +
                (key.edgeRecords ? sizeof(gpu::EdgeRecord) : 0);
  extra.largestBuffer = std::max<uint64_t>({uint64_t(key.tapeVertices) * sizeof(gpu::TapeVertex),
                                            key.shadowAdjoint ? gpu::kShadowRaysPerPath * sizeof(gpu::ShadowAdjoint) : 0,
                                            key.edgeRecords ? sizeof(gpu::EdgeRecord) : 0});
  const uint64_t edgeBytes = edgeBuffer ? edgeBuffer->size() + deviceScene.edgeFaces().size() : 0;
  // Fail before the film is allocated, naming what the render would need.
  RenderMemory need = filmAndBatchNeed(width, height, layers, channels, lanes, extra);
  need.film = filmBytes;  // none for an adjoint render without its image
  need.scene = gpuScene.bytes + edgeBytes;
  const uint64_t budget = checkRenderMemory(context, need, options.memoryBudget);
  ChunkedBuffer& film = m_impl->filmFor(filmFloats);
  key.batchSize = batchSizeFor(budget - filmBytes, layers, lanes,
                               context.properties().limits.maxStorageBufferRange, totalPaths * slotsPerSample,
                               context.properties().limits.maxComputeWorkGroupCount[0], extra);
  const uint32_t batchSize = key.batchSize;
  const uint32_t samplesPerBatch = batchSize / slotsPerSample;
  FrameResources& resources = m_impl->frameResources(key);
  WavefrontBuffers& wave = resources.wave;
  // Where the scene is read through texel views (CPU devices), the path states and hits are too
  // (shade 1.2x faster on the default room), if a batch's path states fit one view.
  const bool waveTexels = gpuScene.texels() && fitsTexelView(context, wave.paths);
  BufferView pathTexels, hitTexels;
  if (waveTexels) {
    pathTexels = texelView(context, wave.paths, "wavefront.pathTexels");
    hitTexels = texelView(context, wave.hits, "wavefront.hitTexels");
  }

  // Forward-mode inputs: per-lane vertex velocities and what each lane differentiates.
  std::optional<Buffer> velocityBuffer, laneBuffer;
  // Point lights follow the emitting triangles in the light table, whose number an update can
  // change (a deformed emitter's triangle of zero area drops out): taken from the table this render
  // uses, not from when the gradient's accumulators were laid out.
  const uint32_t firstPointLight = uint32_t(prepared.lights.size() - deviceScene.scene().pointLights.size());
  if (lanes > 0) {
    std::vector<glm::vec4> velocities(std::max<size_t>(1, size_t(lanes) * prepared.vertices.size()), glm::vec4(0.0f));
    for (uint32_t k = 0; k < lanes; ++k)
      for (size_t v = 0; v < options.derivativeLanes[k].vertexVelocity.size(); ++v)
        velocities[k * prepared.vertices.size() + v] = glm::vec4(options.derivativeLanes[k].vertexVelocity[v], 0.0f);
    velocityBuffer = uploaded(context, velocities, "derivative.vertexVelocity");
    laneBuffer = uploaded(context, laneTable(options.derivativeLanes, firstPointLight), "derivative.lanes");
  }

  gpu::FrameUniforms frame = sceneFrameUniforms(setup.camera, settings, prepared, gpuScene);
  setGateUniforms(frame, setup.gate, options.gateCutoff);
  frame.cameraForward.w = setup.pathOffset;
  frame.gateInfo.z = plan.nee == NeeMode::Ellipsoidal ? gpu::kNeeEllipsoidal
                     : plan.nee == NeeMode::Mis     ? gpu::kNeeMis
                                                    : gpu::kNeeStandard;
  frame.pathInfo = glm::uvec4(settings.rouletteDepth, plan.firstEllipsoidVertex, channels, batchSize);
  frame.chunkShift.z = film.shift;
  frame.edgeInfo = glm::uvec4(edgeCount, edges ? uint32_t(totalPaths) : 0u, 0, 0);
  // resolve divides by the samples every pixel's sums saw: a splatted sample counts in every pixel
  // of its view.
  if (splat) frame.image.z = uint32_t(totalPaths / viewCount);
  std::vector<glm::vec4> records;
  if (views) {
    uint32_t stride = 0;
    records = viewRecords(*views, setup, deviceScene, gpuScene, stride);
    frame.image.y = height;
    frame.viewInfo.x = viewCount;
    frame.viewInfo.z = stride;
  }
  if (adjoint) {
    const GradientLayout& g = adjoint->gradient->layout();
    frame.gradientLayout = glm::uvec4(g.materials, g.emission, g.lights, g.vertices);
    frame.adjointInfo = glm::uvec4(firstPointLight, 0, 0, 0);
    // What a sample's contribution to its pixel's mean is weighted by (adjointOf): one over the
    // samples per pixel, or over the samples of the view of a splatted render.
    const double samplesPerMean = splat ? double(totalPaths / viewCount) : double(totalPaths) / double(pixels);
    frame.adjointScale = glm::vec4(float(adjoint->scale), float(samplesPerMean), 0, 0);
  }
  const Buffer& frameBuffer =
      grownBuffer(context, m_impl->frameBlock, sizeof frame + records.size() * sizeof(glm::vec4), MemoryKind::Device, "frame");

  BindingTable table;
  table.setScene(gpuScene);
  table.set(gpu::kBindingFrame, frameBuffer);
  table.set(gpu::kBindingPaths, wave.paths);
  table.setTexels(gpu::kBindingPathTexels, pathTexels);
  table.setTexels(gpu::kBindingHitTexels, hitTexels);
  table.set(gpu::kBindingHits, wave.hits);
  table.set(gpu::kBindingRayQueues, wave.rayQueues);
  table.set(gpu::kBindingShadowQueue, wave.shadowQueue);
  table.set(gpu::kBindingCounters, wave.counters);
  table.set(gpu::kBindingDispatchArgs, wave.dispatchArgs);
  table.set(gpu::kBindingPathAccum, wave.pathAccum);
  table.setChunks(gpu::kBindingFilm, film);
  if (edgeBuffer) table.set(gpu::kBindingEdges, *edgeBuffer);
  // Bindings 25-28: the meaning this kind of render gives them (shared.h).
  if (lanes > 0) {
    table.set(gpu::kBindingVertexVelocity, *velocityBuffer);
    table.set(gpu::kBindingLanes, *laneBuffer);
    table.set(gpu::kBindingPathDerivs, wave.pathDerivs);
    table.set(gpu::kBindingShadowDerivs, wave.shadowDerivs);
  }
  if (adjoint) {
    table.set(gpu::kBindingAdjointImage, *adjoint->image);
    table.set(gpu::kBindingGradient, adjoint->gradient->buffer());
    table.set(gpu::kBindingTape, resources.tape);
    table.set(gpu::kBindingShadowAdjoint, resources.shadowAdjoint);
  }
  if (edges) {
    table.set(gpu::kBindingEdgeRecords, resources.edgeRecords);
    table.set(gpu::kBindingEdgeFaces, deviceScene.edgeFaces());
  }
  DescriptorSet set(context, pipelines, table, m_impl->dummy);

  SpecValues spec{};
  spec[gpu::kSpecMaterialMask] = prepared.materialMask;
  spec[gpu::kSpecNeeMode] = frame.gateInfo.z;
  spec[gpu::kSpecGateType] = uint32_t(setup.gate.type);
  spec[gpu::kSpecCameraType] = uint32_t(setup.camera.type);
  spec[gpu::kSpecLightMask] = prepared.lightMask;
  spec[gpu::kSpecLanes] = std::max(lanes, 1u);
  spec[gpu::kSpecTerm] = term.specTerm;
  spec[gpu::kSpecAntithetic] = options.antithetic ? 1u : 0u;
  spec[gpu::kSpecAdjointTargets] = adjoint ? adjoint->targets | (adjointImage ? gpu::kAdjointImage : 0u) : 0u;
  spec[gpu::kSpecEllipsoidSelection] =
      plan.ellipsoidSelection == EllipsoidSelection::Enumerate ? gpu::kEllipsoidEnumerate : gpu::kEllipsoidDescend;
  spec[gpu::kSpecCameraConnections] = term.cameraConnections ? 1u : 0u;
  spec[gpu::kSpecSingleChunk] = gpuScene.singleChunk() && film.single() ? 1u : 0u;
  spec[gpu::kSpecSceneTexels] = gpuScene.texels() ? 1u : 0u;
  spec[gpu::kSpecWaveTexels] = waveTexels ? 1u : 0u;
  spec[gpu::kSpecWideBvh] = gpuScene.wideBvh() ? 1u : 0u;
  spec[gpu::kSpecMultiView] = views ? 1u : 0u;
  // VKTG_SHADOW_SLOTS=filled|all overrides the device's choice (tests): the same bits either way.
  spec[gpu::kSpecFilledSlotsOnly] = forcedChoice("VKTG_SHADOW_SLOTS", "filled", "all").value_or(context.isCpuDevice()) ? 1u : 0u;
  spec[gpu::kSpecEdgeStrategy] = gpu::kEdgeStrategyCount;
  // A GPU sums a subgroup's adds to a shared accumulator before its atomic (lib/adjoint.glsl); a CPU
  // device, whose atomics do not queue that way, adds each. VKTG_SCATTER=aggregate|direct
  // overrides (tests): the same bits either way. (Read by every render: a bad value is an error.)
  const bool aggregateScatter = forcedChoice("VKTG_SCATTER", "aggregate", "direct").value_or(!context.isCpuDevice());
  spec[gpu::kSpecScatterAggregate] = adjoint && aggregateScatter ? 1u : 0u;
  // The edge samples and the camera's connections draw their main choice from one stratified
  // sequence per render (rng.glsl stratifiedUnit; docs/theory.md 3.7). VKTG_BOUNDARY_SAMPLES=
  // stratified|independent overrides (tests and benchmarks compare the two).
  const bool stratified = forcedChoice("VKTG_BOUNDARY_SAMPLES", "stratified", "independent").value_or(true);
  spec[gpu::kSpecStratifiedBoundary] = stratified ? 1u : 0u;
  // Edge samples are sorted by strategy, then each strategy's pipeline runs over its own (the
  // reasons: sample_edges.comp); VKTG_EDGE_DISPATCH=single runs one pipeline for all over every
  // sample (tests: the same samples either way). (Read by every render, so that a bad value is an
  // error wherever it is set.)
  const bool strategiesApart = forcedChoice("VKTG_EDGE_DISPATCH", "split", "single").value_or(true);
  const TermPipelines passes =
      termPipelines(pipelines, term, mode, spec, term.strategies && strategiesApart, adjointImage, filmElements > 0);
  VkPipelineLayout layout = pipelines.layout();
  VkDescriptorSet ds = set.get();

  const uint32_t maxDepth = settings.maxDepth;
  // + resolve in the last batch, + 6 when the edges are sampled a strategy at a time, + 1 for an
  // adjoint render's image
  PassProfiler profiler(context, 16 + 6 * maxDepth, options.profile);
  CommandBuffer cmdBuffer(context, "render batch");
  VkCommandBuffer cmd = cmdBuffer.get();
  BatchCommands batch(cmd, layout, profiler, wave, passes);

  // What the host reads after the last batch, where it cannot read the device's buffers directly:
  // copied by that batch's own commands (no submission of its own).
  const bool countersCopied = !wave.counters.mapped();
  // (A film of several chunks, beyond a storage buffer's range, goes back a chunk at a time through
  // one chunk's staging: a copy of all of it would need as much host-visible memory again.)
  const bool filmCopied = filmElements > 0 && !film.chunks.front().hostReadable() && film.single();
  const uint64_t countersBytes = gpu::kCounterCount * sizeof(uint32_t);
  if (countersCopied) grownBuffer(context, m_impl->countersReadback, countersBytes, MemoryKind::Readback, "counters.readback");
  if (filmCopied) grownBuffer(context, m_impl->filmReadback, filmBytes, MemoryKind::Readback, "film.readback");
  // The render's own state, in its first submission: the frame block (at most 64 KiB per update),
  // and the statistics counters and film, which accumulate over all batches.
  auto startRender = [&] {
    recordUpdate(cmd, frameBuffer, &frame, sizeof frame, 0);
    recordUpdate(cmd, frameBuffer, records.data(), records.size() * sizeof(glm::vec4), sizeof frame);
    vkCmdFillBuffer(cmd, wave.counters.handle(), 0, VK_WHOLE_SIZE, 0);
    for (const Buffer& b : film.chunks) vkCmdFillBuffer(cmd, b.handle(), 0, VK_WHOLE_SIZE, 0);
    if (adjoint && adjoint->clearFirst) adjoint->gradient->recordClear(cmd);
    if (adjoint && adjoint->imageStaging) {
      VkBufferCopy region{0, 0, std::min(adjoint->imageStaging->size(), adjoint->image->size())};
      vkCmdCopyBuffer(cmd, adjoint->imageStaging->handle(), adjoint->image->handle(), 1, &region);
    }
  };
  // The last batch's commands after its paths: the film's resolve and the copies for the host.
  auto finishRender = [&] {
    if (passes.resolve != VK_NULL_HANDLE) batch.resolve(filmElements);
    if (adjoint && adjoint->copyBack) adjoint->gradient->recordCopyBack(cmd);
    if (countersCopied) {
      VkBufferCopy region{0, 0, countersBytes};
      vkCmdCopyBuffer(cmd, wave.counters.handle(), m_impl->countersReadback.handle(), 1, &region);
    }
    if (filmCopied) {
      VkBufferCopy region{0, 0, filmBytes};
      vkCmdCopyBuffer(cmd, film.chunks.front().handle(), m_impl->filmReadback.handle(), 1, &region);
    }
  };

  auto start = std::chrono::steady_clock::now();
  uint64_t done = 0;
  while (done < totalPaths) {
    throwIfInterrupted();
    uint32_t active = uint32_t(std::min<uint64_t>(samplesPerBatch, totalPaths - done));
    uint32_t firstSample = uint32_t((done + firstPixel) / pixels);
    uint32_t firstLinear = uint32_t(done + firstPixel - uint64_t(firstSample) * pixels);
    cmdBuffer.begin();
    profiler.reset(cmd);
    if (done == 0) startRender();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &ds, 0, nullptr);
    batch.clearBatchState(batchSize);
    // Splatted samples are numbered across the render, per-pixel paths from their pixel.
    batch.startSamples(splat ? uint32_t(done) : firstLinear, firstSample, active);
    if (term.bounces) {
      for (uint32_t depth = 0; depth < maxDepth; ++depth) batch.bounce(depth);
    } else {
      batch.traceShadowRays();
    }
    // The adjoint's last step, then the film's accumulation (an adjoint render's only with its image).
    if (passes.finish != VK_NULL_HANDLE) batch.finishPaths(uint64_t(active) * slotsPerSample);
    if (passes.accumulate != VK_NULL_HANDLE) batch.accumulate(firstLinear, result.stats.batches, active, pixels, filmElements);
    if (passes.splats != VK_NULL_HANDLE) batch.accumulateSplats(active, layers, lanes);
    if (done + active == totalPaths) finishRender();
    hostReadBarrier(cmd);  // the counters (and a mapped film) are read by the host after the fence
    cmdBuffer.end();
    context.submitAndWait(cmd);
    profiler.collect();
    done += active;
    result.stats.batches++;
    if (options.progress) options.progress(double(done) / double(totalPaths));
    throwIfInterrupted();
  }
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<uint32_t> counters(gpu::kCounterCount);
  (countersCopied ? m_impl->countersReadback : wave.counters).download(context, counters.data(), countersBytes);
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
  stats.gradientOverflows = counters[gpu::kCounterGradientOverflow];
  stats.silhouetteEdges = edgeCount;
  stats.batchSize = batchSize;
  stats.deviceBytes = gpuScene.bytes + resources.bytes() + filmBytes + edgeBytes;
  stats.sceneTexels = gpuScene.texels();
  stats.wideBvh = gpuScene.wideBvh();
  stats.waveTexels = waveTexels;
  stats.bufferChunks = uint32_t(
      std::max({gpuScene.triangles.chunks.size(), gpuScene.bvhNodes.chunks.size(), film.chunks.size()}));
  result.passMilliseconds = profiler.millisecondsPerPass();
  if (filmElements == 0) return result;

  std::vector<float> resolved(filmFloats), mean(filmElements), variance(filmElements);
  if (filmCopied) {
    m_impl->filmReadback.download(context, resolved.data(), filmBytes);
  } else {
    const size_t perChunk = size_t(1) << film.shift;
    for (size_t c = 0; c < film.chunks.size(); ++c) {
      const size_t first = c * perChunk, count = std::min<size_t>(perChunk, filmFloats - first);
      Buffer* staging = film.chunks[c].hostReadable() ? nullptr
                                                      : &grownBuffer(context, m_impl->filmReadback, count * sizeof(float),
                                                                     MemoryKind::Readback, "film.readback");
      film.chunks[c].download(context, resolved.data() + first, count * sizeof(float), 0, staging);
    }
  }
  for (size_t i = 0; i < filmElements; ++i) {
    mean[i] = resolved[gpu::kFilmFloatsPerElement * i];
    variance[i] = resolved[gpu::kFilmFloatsPerElement * i + 1];
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
      std::string name = setup.gate.layerName(k);
      m.layers.push_back({name, layerOf(mean, c, k)});
      v.layers.push_back({name, layerOf(variance, c, k)});
    }
  }
  return result;
}

}  // namespace vktg
