#include "render/device_scene.h"

#include <algorithm>

#include "render/frame_uniforms.h"
#include "vktg/bvh.h"
#include "vktg/error.h"
#include "vktg/shader_registry.h"
#include "vktg/silhouette_edges.h"

namespace vktg {
namespace {

// Nodes one invocation of bvh_sah_cost sums, in order: few enough partial sums for the host, enough
// invocations for the device.
constexpr uint32_t kSahNodesPerInvocation = 64;

template <class T>
Buffer deviceArray(const VulkanContext& context, const std::vector<T>& data, const std::string& name) {
  Buffer buffer(context, std::max<size_t>(16, data.size() * sizeof(T)), MemoryKind::Device, name);
  buffer.upload(context, data.data(), data.size() * sizeof(T));
  return buffer;
}

uint32_t groupsFor(uint64_t items, const VulkanContext& context, const char* what) {
  uint64_t groups = (items + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize;
  if (groups > context.properties().limits.maxComputeWorkGroupCount[0])
    throw Error(std::string("scene update: ") + std::to_string(items) + " " + what + " exceed one dispatch on this device");
  return uint32_t(groups);
}

}  // namespace

// What the scene-update passes need besides the scene buffers.
struct DeviceScene::UpdateResources {
  UpdateResources(VulkanContext& context, const ParameterModel& model)
      : pipelines(PassPipelines::shared(context, kShaderRegistry,
                                        [&] {
                                          std::filesystem::path file = defaultPipelineCacheFile(context);
                                          return file.empty() ? file : file.concat("-update");
                                        }(),
                                        gpu::kUpdateBindingCount)),
        dummy(context, 256, MemoryKind::Device, "update.dummy"),
        frame(context, sizeof(gpu::FrameUniforms), MemoryKind::Device, "update.frame") {
    VertexOpTables tables = model.deviceTables();
    std::vector<glm::vec4> base;
    for (const Shape& s : model.baseScene().shapes)
      for (const glm::vec3& p : s.positions) base.emplace_back(p, 1.0f);
    basePositions = deviceArray(context, base, "update.basePositions");
    vertexOps = deviceArray(context, tables.vertexOps, "update.vertexOps");
    opList = deviceArray(context, tables.opList, "update.opList");
    parameterOps = deviceArray(context, tables.parameterOps, "update.parameterOps");
    theta = Buffer(context, std::max<size_t>(16, model.size() * sizeof(float)), MemoryKind::Device, "update.theta");
  }
  std::shared_ptr<PassPipelines> pipelines;
  Buffer dummy, frame, basePositions, vertexOps, opList, parameterOps, theta, refitOrder, sahPartials;
  BvhRefitOrder levels;
};

DeviceScene::DeviceScene(VulkanContext& context, const Scene& scene) : m_context(context), m_scene(scene) {
  for (const PointLight& light : scene.pointLights) m_lightBase.push_back(light.position);
  m_lightsAtTheta = m_lightBase;
  build(scene);
}

DeviceScene::DeviceScene(VulkanContext& context, const ParameterModel& model, std::span<const double> theta,
                         std::span<const double> buildTheta)
    : m_context(context), m_model(&model), m_buildTheta(buildTheta.begin(), buildTheta.end()) {
  m_update = std::make_unique<UpdateResources>(context, model);
  m_movingShapes = model.movingShapes();
  for (const PointLight& light : model.baseScene().pointLights) m_lightBase.push_back(light.position);
  Scene atBuild = model.sceneAt(buildTheta);
  m_scene = atBuild;
  build(atBuild);
  update(theta, false);
}

DeviceScene::~DeviceScene() = default;

void DeviceScene::build(const Scene& sceneAtBuild) {
  m_prepared = prepareScene(sceneAtBuild);
  if (m_model) {
    for (size_t s = 0; s < m_movingShapes.size(); ++s) m_prepared.shapes[s].flags = m_movingShapes[s] ? gpu::kShapeMoves : 0u;
  }
  m_gpu = std::make_unique<GpuScene>(m_context, m_prepared);
  m_buildCost = bvhSahCost(m_prepared.bvh);
  m_emitterTriangles.clear();
  for (uint32_t i = 0; i < m_prepared.triangles.size(); ++i)
    if (sceneAtBuild.shapes[m_prepared.triangleVerts[i].w].emission > 0) m_emitterTriangles.push_back(i);
  if (m_update) {
    m_update->levels = bvhRefitOrder(m_prepared.bvh);
    m_update->refitOrder = deviceArray(m_context, m_update->levels.nodes, "update.refitOrder");
  }
  if (m_edgesBuilt) {
    m_edgesBuilt = false;
    edges(std::vector<bool>(m_edgeMoving), std::vector<bool>(m_edgeDeforming));
  }
}

void DeviceScene::update(std::span<const double> theta, bool checkQuality) {
  if (!m_model) throw Error("internal: update() of a scene without parameters");
  m_theta.assign(theta.begin(), theta.end());
  m_model->setScalars(m_scene, theta);
  m_lightsAtTheta.clear();
  for (const PointLight& light : m_scene.pointLights) m_lightsAtTheta.push_back(light.position);
  if (m_model->movesVertices()) {
    std::vector<float> values(theta.begin(), theta.end());
    m_update->theta.upload(m_context, values.data(), values.size() * sizeof(float));
    // The check: the refit tree's SAH cost, summed on the device right after the refit (the same
    // bits on a given device for the same θ), against its cost when built. Only the vertices move:
    // the whole scene at θ is made only to rebuild.
    const double refitCost = runUpdatePasses(true, checkQuality);
    if (checkQuality) {
      m_lastSahRatio = refitCost / m_buildCost;
      if (m_lastSahRatio > kBvhRebuildRatio) {
        m_buildTheta = m_theta;
        Scene now = m_model->sceneAt(theta);
        build(now);
        m_scene.shapes = now.shapes;
        m_rebuilds++;
        runUpdatePasses(true);
      }
    }
  }
  uploadTables();
}

void DeviceScene::uploadTables() {
  for (size_t s = 0; s < m_prepared.shapes.size(); ++s) m_prepared.shapes[s].emission = m_scene.shapes[s].emission;
  // Emitters the parameters deform change their triangles' areas, hence the light selection.
  if (m_model && m_model->movesVertices()) {
    std::vector<uint32_t> firstVertex(m_scene.shapes.size() + 1, 0);
    for (size_t s = 0; s < m_scene.shapes.size(); ++s)
      firstVertex[s + 1] = firstVertex[s] + uint32_t(m_scene.shapes[s].positions.size());
    for (uint32_t s = 0; s < m_movingShapes.size(); ++s) {
      if (!m_movingShapes[s] || !(m_scene.shapes[s].emission > 0)) continue;
      std::vector<glm::dvec3> p = m_model->shapePositions(m_theta, s);
      for (uint32_t i : m_emitterTriangles) {
        const glm::uvec4& ids = m_prepared.triangleVerts[i];
        if (ids.w != s) continue;
        glm::dvec3 a = p[ids.x - firstVertex[s]], b = p[ids.y - firstVertex[s]], c = p[ids.z - firstVertex[s]];
        m_prepared.triangles[i].p2.w = float(0.5 * glm::length(glm::cross(b - a, c - a)));
      }
    }
  }
  for (size_t m = 0; m < m_prepared.materials.size(); ++m) {
    const Material& material = m_scene.materials[m];
    m_prepared.materials[m].albedo = material.albedo;
    m_prepared.materials[m].roughness = material.roughness;
    m_prepared.materials[m].ior = material.ior;
  }
  prepareLights(m_prepared, m_scene, &m_emitterTriangles);
  if (m_prepared.lights.size() * sizeof(gpu::GpuLight) > m_gpu->lights.size())
    throw Error("scene: an emitter was deformed into more light entries than the scene was built with");
  m_gpu->shapes.upload(m_context, m_prepared.shapes.data(), m_prepared.shapes.size() * sizeof(gpu::GpuShape));
  m_gpu->materials.upload(m_context, m_prepared.materials.data(), m_prepared.materials.size() * sizeof(gpu::GpuMaterial));
  m_gpu->lights.upload(m_context, m_prepared.lights.data(), m_prepared.lights.size() * sizeof(gpu::GpuLight));
}

std::vector<glm::vec3> DeviceScene::pointLightsFor(const std::vector<std::pair<uint32_t, glm::vec3>>& viewPositions) const {
  std::vector<glm::vec3> placed = m_lightsAtTheta;
  for (const auto& [light, position] : viewPositions) {
    if (light >= placed.size()) throw Error("internal: point light index out of range");
    placed[light] = position + (m_lightsAtTheta[light] - m_lightBase[light]);
  }
  return placed;
}

void DeviceScene::placePointLights(const std::vector<std::pair<uint32_t, glm::vec3>>& viewPositions) {
  const std::vector<glm::vec3> placed = pointLightsFor(viewPositions);
  bool changed = false;
  for (size_t i = 0; i < placed.size(); ++i)
    if (m_scene.pointLights[i].position != placed[i]) {
      m_scene.pointLights[i].position = placed[i];
      changed = true;
    }
  if (!changed) return;
  prepareLights(m_prepared, m_scene, &m_emitterTriangles);
  m_gpu->lights.upload(m_context, m_prepared.lights.data(), m_prepared.lights.size() * sizeof(gpu::GpuLight));
}

const Buffer& DeviceScene::edges(const std::vector<bool>& movingVertex, const std::vector<bool>& deformingVertex) {
  if (m_edgesBuilt && movingVertex == m_edgeMoving && deformingVertex == m_edgeDeforming) return m_edgeBuffer;
  EdgeList list = edgeList(m_prepared, movingVertex, deformingVertex);
  m_edgeMoving = movingVertex;
  m_edgeDeforming = deformingVertex;
  m_edgeCount = uint32_t(list.edges.size());
  m_edgeBuffer = deviceArray(m_context, list.edges, "scene.edges");
  m_edgeFaces = deviceArray(m_context, list.faces, "scene.edgeFaces");
  m_edgesBuilt = true;
  // The list was made from the positions of the last build; bring it to the device's.
  if (m_model && m_model->movesVertices()) runUpdatePasses(false);
  return m_edgeBuffer;
}

double DeviceScene::runUpdatePasses(bool moveGeometry, bool measureSah) {
  UpdateResources& u = *m_update;
  gpu::FrameUniforms frame = sceneFrameUniforms(m_scene.camera, m_scene.render, m_prepared, *m_gpu);
  frame.edgeInfo.x = m_edgesBuilt ? m_edgeCount : 0u;
  u.frame.upload(m_context, &frame, sizeof frame);
  BindingTable table;
  table.setScene(*m_gpu);
  table.set(gpu::kBindingFrame, u.frame);
  table.set(gpu::kUpdateBindingBasePositions, u.basePositions);
  table.set(gpu::kUpdateBindingVertexOps, u.vertexOps);
  table.set(gpu::kUpdateBindingOpList, u.opList);
  table.set(gpu::kUpdateBindingParameterOps, u.parameterOps);
  table.set(gpu::kUpdateBindingTheta, u.theta);
  table.set(gpu::kUpdateBindingRefitOrder, u.refitOrder);
  if (m_gpu->wideBvh()) table.set(gpu::kUpdateBindingWideBvhNodes, m_gpu->wideBvhNodes);
  if (m_edgesBuilt) {
    table.set(gpu::kUpdateBindingEdges, m_edgeBuffer);
    table.set(gpu::kUpdateBindingEdgeFaces, m_edgeFaces);
  }
  // bvh_sah_cost's partial sums, one per invocation of kSahNodesPerInvocation nodes, written where
  // the host reads them.
  const uint32_t nodes = uint32_t(m_prepared.bvh.nodes.size());
  const bool sumSah = measureSah && moveGeometry && nodes > 1;
  const uint32_t sahInvocations = sumSah ? (nodes + kSahNodesPerInvocation - 1) / kSahNodesPerInvocation : 0u;
  if (sumSah) {
    const uint64_t bytes = uint64_t(sahInvocations) * sizeof(float);
    if (u.sahPartials.size() < bytes) u.sahPartials = Buffer(m_context, bytes, MemoryKind::Readback, "update.sahPartials");
    table.set(gpu::kUpdateBindingSahPartials, u.sahPartials);
  }
  DescriptorSet set(m_context, *u.pipelines, table, u.dummy);
  SpecValues spec{};
  spec[gpu::kSpecSingleChunk] = m_gpu->singleChunk() ? 1u : 0u;
  // kSpecSceneTexels stays 0: these passes write the nodes they read (refit_bvh).
  // The first update creates the passes' pipelines together (in parallel on a GPU).
  std::vector<std::pair<std::string, SpecValues>> passes;
  if (moveGeometry) passes = {{"move_vertices", spec}, {"update_triangles", spec}, {"refit_bvh", spec}};
  if (moveGeometry && m_gpu->wideBvh()) passes.push_back({"refit_wide_bvh", spec});
  if (m_edgesBuilt) passes.push_back({"update_edges", spec});
  if (sumSah) passes.push_back({"bvh_sah_cost", spec});
  u.pipelines->prepare(passes);
  CommandBuffer cmdBuffer(m_context, "scene update");
  cmdBuffer.begin();
  VkCommandBuffer cmd = cmdBuffer.get();
  VkDescriptorSet ds = set.get();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, u.pipelines->layout(), 0, 1, &ds, 0, nullptr);
  auto dispatch = [&](const char* pass, uint32_t groups, glm::uvec4 push) {
    if (groups == 0) return;
    m_context.beginLabel(cmd, pass);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, u.pipelines->get(pass, spec));
    vkCmdPushConstants(cmd, u.pipelines->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    vkCmdDispatch(cmd, groups, 1, 1);
    m_context.endLabel(cmd);
    computeBarrier(cmd);
  };
  if (moveGeometry) {
    dispatch("move_vertices", groupsFor(m_prepared.vertices.size(), m_context, "vertices"), glm::uvec4(0));
    dispatch("update_triangles", groupsFor(m_prepared.triangles.size(), m_context, "triangles"), glm::uvec4(0));
    const BvhRefitOrder& levels = u.levels;
    for (size_t l = 0; l + 1 < levels.levelStart.size(); ++l) {
      uint32_t first = levels.levelStart[l], count = levels.levelStart[l + 1] - first;
      dispatch("refit_bvh", groupsFor(count, m_context, "BVH nodes"), glm::uvec4(first, 0, 0, count));
    }
    if (m_gpu->wideBvh()) {
      const uint32_t wide = uint32_t(m_gpu->wideBvhNodes.size() / sizeof(gpu::GpuWideBvhNode));
      dispatch("refit_wide_bvh", groupsFor(wide, m_context, "wide BVH nodes"), glm::uvec4(0, 0, 0, wide));
    }
  }
  if (m_edgesBuilt) dispatch("update_edges", groupsFor(m_edgeCount, m_context, "edges"), glm::uvec4(0));
  if (sumSah) {
    dispatch("bvh_sah_cost", groupsFor(sahInvocations, m_context, "BVH nodes"), glm::uvec4(sahInvocations, 0, 0, nodes));
    hostReadBarrier(cmd);
  }
  cmdBuffer.end();
  m_context.submitAndWait(cmd);
  if (!measureSah) return 0.0;
  // A tree of one leaf costs its triangle count; otherwise the root's visit plus the shares, added
  // in order.
  if (!sumSah) return bvhSahCost(m_prepared.bvh);
  std::vector<float> partials(sahInvocations);
  u.sahPartials.download(m_context, partials.data(), partials.size() * sizeof(float));
  double cost = 1.0;
  for (float p : partials) cost += p;
  return cost;
}

}  // namespace vktg
