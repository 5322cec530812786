#include "vktg/prepared_scene.h"

#include <bit>
#include <cmath>

#include "scene/selection_cdf.h"
#include "vktg/error.h"

namespace vktg {
namespace {

constexpr float kPi = 3.14159265358979f;

float triangleArea(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2) {
  return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
}

}  // namespace

PreparedScene prepareScene(const Scene& scene) {
  PreparedScene out;
  std::vector<BvhTriangle> soup;
  std::vector<glm::uvec4> verts;  // input order
  for (uint32_t s = 0; s < scene.shapes.size(); ++s) {
    const Shape& shape = scene.shapes[s];
    uint32_t base = uint32_t(out.vertices.size());
    for (glm::vec3 p : shape.positions) out.vertices.emplace_back(p, 1.0f);
    for (glm::uvec3 t : shape.triangles) {
      soup.push_back({shape.positions[t.x], shape.positions[t.y], shape.positions[t.z]});
      verts.emplace_back(t.x + base, t.y + base, t.z + base, s);
    }
    gpu::GpuShape gs{};
    gs.material = shape.material;
    gs.emission = shape.emission;
    out.shapes.push_back(gs);
  }
  if (soup.empty()) throw Error("scene has no triangles");
  out.bvh = buildBvh(soup);

  out.triangles.resize(soup.size());
  out.triangleVerts.resize(soup.size());
  for (uint32_t i = 0; i < soup.size(); ++i) {
    uint32_t src = out.bvh.order[i];
    const BvhTriangle& t = soup[src];
    uint32_t shape = verts[src].w;
    out.triangles[i].p0 = glm::vec4(t.p0, std::bit_cast<float>(shape));
    out.triangles[i].p1 = glm::vec4(t.p1, std::bit_cast<float>(src));
    out.triangles[i].p2 = glm::vec4(t.p2, triangleArea(t.p0, t.p1, t.p2));
    out.triangleVerts[i] = verts[src];
  }

  for (const Material& m : scene.materials) {
    gpu::GpuMaterial gm{};
    gm.type = uint32_t(m.type);
    gm.albedo = m.albedo;
    gm.roughness = m.roughness;
    gm.ior = m.ior;
    out.materials.push_back(gm);
  }
  for (const Shape& shape : scene.shapes) out.materialMask |= 1u << uint32_t(scene.materials.at(shape.material).type);

  prepareLights(out, scene);
  sceneBounds(scene, out.boundsMin, out.boundsMax);
  return out;
}

void prepareLights(PreparedScene& out, const Scene& scene, const std::vector<uint32_t>* emitters) {
  out.lights.clear();
  out.lightMask = 0;
  // Light selection proportional to emitted power.
  std::vector<double> power;
  auto visit = [&](uint32_t i) {
    float emission = out.shapes[out.triangleVerts[i].w].emission;
    float area = out.triangles[i].p2.w;
    if (emission <= 0 || area <= 0) return;
    gpu::GpuLight light{};
    light.type = gpu::kLightAreaTriangle;
    light.triangle = i;
    out.lights.push_back(light);
    power.push_back(double(kPi) * emission * area);
    out.lightMask |= 1u << gpu::kLightAreaTriangle;
  };
  if (emitters)
    for (uint32_t i : *emitters) visit(i);
  else
    for (uint32_t i = 0; i < out.triangles.size(); ++i) visit(i);
  for (const PointLight& p : scene.pointLights) {
    gpu::GpuLight light{};
    light.type = gpu::kLightPoint;
    light.positionIntensity = glm::vec4(p.position, p.intensity);
    out.lights.push_back(light);
    power.push_back(4.0 * double(kPi) * p.intensity);
    out.lightMask |= 1u << gpu::kLightPoint;
  }
  double total = 0;
  for (double p : power) total += p;
  if (out.lights.empty() || !(total > 0)) throw Error("scene has no light: add an emissive shape or a point light");
  // The device divides by the total as a float (areaLightPdf).
  if (!std::isfinite(float(total)))
    throw Error("the scene's emitted power (pi x emission x area over every emitter, 4 pi x intensity per point "
                "light) is past the float range");
  // In 24-bit fixed point (selection_cdf.h): the shaders draw 24-bit numbers k / 2^24 and every
  // end and width is a float exactly, so each light is picked with exactly its pmf, however many
  // emitting triangles there are.
  const uint64_t scale = uint64_t(1) << 24;
  if (out.lights.size() > scale) throw Error("scene has more than 2^24 lights (emitting triangles and point lights)");
  const std::vector<uint64_t> ends = selectionIntervalEnds(power, scale);
  uint64_t start = 0;
  for (size_t i = 0; i < out.lights.size(); ++i) {
    out.lights[i].pmf = float(double(ends[i] - start) / double(scale));
    out.lights[i].cdf = float(double(ends[i]) / double(scale));
    start = ends[i];
  }
  out.totalLightPower = float(total);
}

}  // namespace vktg
