#include <limits>
#include <numbers>

#include "vktg/scene.h"

#include "scene/primitives.h"

namespace vktg {

size_t Scene::triangleCount() const {
  size_t count = 0;
  for (const Shape& shape : shapes) count += shape.triangles.size();
  return count;
}

double Scene::emittedPower() const {
  constexpr double kPi = std::numbers::pi;
  double power = 0;
  for (const Shape& shape : shapes)
    if (shape.emission > 0) power += kPi * double(shape.emission) * meshArea(shape.positions, shape.triangles);
  for (const PointLight& light : pointLights) power += 4.0 * kPi * double(light.intensity);
  return power;
}

bool Scene::hasEmitters() const {
  for (const Shape& shape : shapes)
    if (shape.emission > 0 && !shape.triangles.empty()) return true;
  for (const PointLight& light : pointLights)
    if (light.intensity > 0) return true;
  return false;
}

void sceneBounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi) {
  // The camera is always part of the scene, so the bounds are never empty.
  lo = hi = scene.camera.position;
  auto grow = [&](const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  };
  for (const Shape& shape : scene.shapes)
    for (const glm::vec3& p : shape.positions) grow(p);
  for (const PointLight& light : scene.pointLights) grow(light.position);
}

}  // namespace vktg
