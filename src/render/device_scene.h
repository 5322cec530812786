// A scene resident on the device across renders (DESIGN.md §3a): geometry, BVH, materials, lights
// and, for edge passes, the edge list, uploaded once and shared by every render, gradient and
// optimisation iteration. With a ParameterModel the scene moves in place: update(θ) uploads θ, and
// the device moves the vertices (move_vertices), refreshes the triangles (update_triangles), refits
// the BVH level by level (refit_bvh) and moves the edge list (update_edges). The host keeps only the
// small tables (materials, shapes, lights, gate) in step. When a quality check finds the refit BVH's
// SAH cost too far above what the tree cost when built, the BVH is rebuilt from the host's scene at θ,
// so the tree at any θ follows from (θ of the last build, θ) alone: a resumed run rebuilds it exactly.
#pragma once
#include <memory>
#include <span>
#include <vector>

#include "render/gpu_scene.h"
#include "render/pass_pipelines.h"
#include "vktg/parameter_model.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {

// How often (in updates) an optimisation compares the refit BVH's SAH cost with the built tree's.
inline constexpr uint64_t kBvhQualityCheckInterval = 8;

// A refit tree is rebuilt once its SAH cost exceeds this multiple of its cost when built.
inline constexpr double kBvhRebuildRatio = 1.5;

class DeviceScene {
 public:
  // A scene that does not move.
  DeviceScene(VulkanContext& context, const Scene& scene);
  // A scene `model`'s parameters move, starting at θ = `theta` with the BVH built at `buildTheta`
  // (a fresh run passes the same vector twice; a resumed one the checkpoint's).
  DeviceScene(VulkanContext& context, const ParameterModel& model, std::span<const double> theta,
              std::span<const double> buildTheta);
  ~DeviceScene();
  DeviceScene(const DeviceScene&) = delete;
  DeviceScene& operator=(const DeviceScene&) = delete;

  // Moves the scene to θ on the device. With `checkQuality`, measures the refit BVH's SAH cost on
  // the device (bvh_sah_cost) and rebuilds the tree when it has degraded past kBvhRebuildRatio.
  void update(std::span<const double> theta, bool checkQuality);

  // The host's view at the current θ: materials, lights, gate, camera and render settings are
  // current; shape positions are those of the last BVH build (the device holds the current ones).
  const Scene& scene() const { return m_scene; }
  const PreparedScene& prepared() const { return m_prepared; }
  const GpuScene& gpu() const { return *m_gpu; }
  const ParameterModel* model() const { return m_model; }
  VulkanContext& context() const { return m_context; }

  // The edge list of the edge passes (edgeList: `movingVertex` per vertex, whose edges get half the
  // selection mass; flat creases at `deformingVertex` kept), built when first asked for or when
  // either set changes, moved with the scene from then on.
  const Buffer& edges(const std::vector<bool>& movingVertex, const std::vector<bool>& deformingVertex);
  uint32_t edgeCount() const { return m_edgeCount; }
  // Per edge of that list, its faces' opposite vertices and triangles (EdgeList::faces).
  const Buffer& edgeFaces() const { return m_edgeFaces; }

  // Places the point lights for one view (a target's laser positions): a light the view names sits
  // at the view's position plus what the parameters move it by at the current θ; every other light
  // sits where θ puts it. Uploads only when a position changes.
  void placePointLights(const std::vector<std::pair<uint32_t, glm::vec3>>& viewPositions);
  // Where placePointLights would put every point light for that view (scene order), without
  // moving them: a render of several views gives each its own (Renderer::render).
  std::vector<glm::vec3> pointLightsFor(const std::vector<std::pair<uint32_t, glm::vec3>>& viewPositions) const;

  std::span<const double> theta() const { return m_theta; }
  std::span<const double> buildTheta() const { return m_buildTheta; }
  uint32_t rebuilds() const { return m_rebuilds; }
  double lastSahRatio() const { return m_lastSahRatio; }  // refit cost / cost when built (1 before any check)

 private:
  void build(const Scene& sceneAtBuild);
  void uploadTables();
  // Records and runs the update's passes; with `measureSah` (and moved geometry) also the refit
  // tree's SAH cost, which it returns (0 otherwise).
  double runUpdatePasses(bool moveGeometry, bool measureSah = false);

  VulkanContext& m_context;
  const ParameterModel* m_model = nullptr;
  Scene m_scene;
  PreparedScene m_prepared;
  std::unique_ptr<GpuScene> m_gpu;
  std::vector<double> m_theta, m_buildTheta;
  std::vector<glm::vec3> m_lightBase;     // point lights as the scene file places them
  std::vector<glm::vec3> m_lightsAtTheta;  // ... and where θ puts them
  // Triangles of shapes that emit (leaf order, ascending): an update visits these alone for the
  // light table, not every triangle (parameters cannot make a shape emit that does not).
  std::vector<uint32_t> m_emitterTriangles;
  std::vector<bool> m_movingShapes;
  double m_buildCost = 0, m_lastSahRatio = 1;
  uint32_t m_rebuilds = 0;

  struct UpdateResources;
  std::unique_ptr<UpdateResources> m_update;

  Buffer m_edgeBuffer, m_edgeFaces;
  std::vector<bool> m_edgeMoving, m_edgeDeforming;
  bool m_edgesBuilt = false;
  uint32_t m_edgeCount = 0;
};

}  // namespace vktg
