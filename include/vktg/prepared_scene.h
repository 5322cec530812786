// The scene flattened into the arrays the GPU reads (BVH order, light CDF). CPU only, so tests
// can check it without a device; src/host/gpu_scene.cpp uploads it.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "vktg/bvh.h"
#include "vktg/gpu/shared.h"
#include "vktg/scene.h"

namespace vktg {

struct PreparedScene {
  Bvh bvh;
  std::vector<gpu::GpuTriangle> triangles;  // leaf order
  std::vector<glm::uvec4> triangleVerts;    // leaf order: global vertex indices i0, i1, i2, shape
  std::vector<glm::vec4> vertices;          // all shapes' positions, concatenated
  std::vector<gpu::GpuShape> shapes;
  std::vector<gpu::GpuMaterial> materials;
  std::vector<gpu::GpuLight> lights;        // selection CDF over emissive triangles and point lights
  float totalLightPower = 0;                // W (area: pi Le A, point: 4 pi I)
  uint32_t materialMask = 0;                // bit per material type in use
  uint32_t lightMask = 0;                   // bit per light type in use
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
};

PreparedScene prepareScene(const Scene& scene);

// (Re)builds the light table (lights, lightMask, totalLightPower) from the shapes' emission
// (out.shapes), the triangle areas (out.triangles[i].p2.w) and the scene's point lights. With
// `emitters` (ascending triangle indices, a superset of those that emit), only those are visited:
// the same table, without a pass over every triangle.
void prepareLights(PreparedScene& out, const Scene& scene, const std::vector<uint32_t>* emitters = nullptr);

}  // namespace vktg
