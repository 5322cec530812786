// The built-in default scene: a Cornell-box-like room seen by a box-gated time-of-flight camera.
// scenes/cornell_box.json and scenes/default_room.xml (Mitsuba 3) describe the same scene (tests
// check that they agree).
#include "scene/primitives.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

void addShape(Scene& scene, const std::string& name, TriangleMesh mesh, const glm::mat4& transform, uint32_t material,
              float emission = 0.0f) {
  transformMesh(mesh, transform);
  Shape shape;
  shape.name = name;
  shape.positions = std::move(mesh.positions);
  shape.triangles = std::move(mesh.triangles);
  shape.material = material;
  shape.emission = emission;
  scene.shapes.push_back(std::move(shape));
}

}  // namespace

Scene defaultScene() {
  Scene scene;
  // Monochrome, so the red and green walls of the classic box become a darker and a brighter grey.
  // Material order matches the JSON file, whose materials are read in name order.
  scene.materials = {{"left", MaterialType::Diffuse, 0.6f}, {"right", MaterialType::Diffuse, 0.4f},
                     {"white", MaterialType::Diffuse, 0.8f}};
  const uint32_t left = 0, right = 1, white = 2;

  // The room spans x, z in [-1, 1] and y in [0, 2], open towards the camera (+z). Every wall is the
  // rectangle primitive (front face +z) rotated so that its front face looks into the room.
  const glm::vec3 one(1.0f);
  addShape(scene, "floor", makeRectangle(), composeTransform({0, 0, 0}, {-90, 0, 0}, one), white);
  addShape(scene, "ceiling", makeRectangle(), composeTransform({0, 2, 0}, {90, 0, 0}, one), white);
  addShape(scene, "back", makeRectangle(), composeTransform({0, 1, -1}, {0, 0, 0}, one), white);
  addShape(scene, "left", makeRectangle(), composeTransform({-1, 1, 0}, {0, 90, 0}, one), left);
  addShape(scene, "right", makeRectangle(), composeTransform({1, 1, 0}, {0, -90, 0}, one), right);
  // A 0.5 m x 0.5 m light facing down, 2 cm below the ceiling so the two never coincide.
  addShape(scene, "light", makeRectangle(), composeTransform({0, 1.98f, 0}, {90, 0, 0}, {0.25f, 0.25f, 1}), white,
           15.0f);
  addShape(scene, "short_box", makeCube(), composeTransform({0.35f, 0.3f, 0.3f}, {0, -17, 0}, {0.3f, 0.3f, 0.3f}),
           white);
  addShape(scene, "tall_box", makeCube(), composeTransform({-0.35f, 0.6f, -0.3f}, {0, 17, 0}, {0.3f, 0.6f, 0.3f}),
           white);

  scene.camera.type = CameraType::Perspective;
  scene.camera.position = {0, 1, 3.8f};
  scene.camera.lookAt = {0, 1, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.fovY = 40.0f;
  scene.camera.width = scene.camera.height = 128;

  // Path lengths (camera -> surface -> light): the light itself is seen at 3.9 m; one-bounce paths
  // run from about 4.5 m (top front of the side walls) to 7.4 m (back floor corners), with the floor
  // centre at 5.9 m and the back wall centre at 6.2 m; two-bounce paths start near 5.5 m. The box
  // [3.5 m, 6.5 m] keeps the directly seen light, most one-bounce paths and the shortest
  // two-bounce ones, and cuts the long interreflection tail.
  scene.gate.type = GateType::Box;
  scene.gate.a = 3.5;
  scene.gate.b = 6.5;

  scene.render.spp = 64;

  // Parameters to differentiate by (the same as scenes/cornell_box.json's): the short box along x,
  // the tall box turning about its vertical axis, the light's emission, the left wall's albedo.
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : scene.shapes.back().positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  scene.parameters = {{"short_box_x", ParameterKind::Translate, "short_box", {1, 0, 0}, {}, {}},
                      {"tall_box_spin", ParameterKind::Rotate, "tall_box", {0, 1, 0}, 0.5f * (lo + hi), {}},
                      {"light_emission", ParameterKind::Emission, "light", {}, {}, {}},
                      {"left_albedo", ParameterKind::Albedo, "left", {}, {}, {}}};
  return scene;
}

}  // namespace vktg
