#include "support/ellipsoid_kernel.h"

namespace vktg::test {

std::vector<EllipsoidSampleIn> ellipsoidInputs(size_t n, uint32_t seed, dvec3 f1, dvec3 f2,
                                               const std::function<float(std::mt19937&)>& length) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<EllipsoidSampleIn> in(n);
  for (EllipsoidSampleIn& x : in) {
    for (int k = 0; k < 3; ++k) {
      x.f1[k] = float(f1[k]);
      x.f2[k] = float(f2[k]);
    }
    x.s = length(rng);
    for (float& u : x.u) u = unit(rng);
    x.line = -1.0f;
  }
  return in;
}

std::vector<EllipsoidSampleIn> planeAndTiltedInputs(size_t n, uint32_t seed,
                                                    const std::function<float(std::mt19937&)>& length) {
  return ellipsoidInputs(n, seed, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, length);
}

std::vector<RefTriangle> planeAndTiltedTriangles() {
  return {{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}},
          {{-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}},
          {{-0.5, -0.5, 0.3}, {0.8, -0.2, 0.6}, {0.0, 0.7, 1.0}}};
}

Shape shapeOfTriangles(const std::string& name, const std::vector<RefTriangle>& triangles) {
  Shape shape;
  shape.name = name;
  for (const RefTriangle& t : triangles) {
    const uint32_t base = uint32_t(shape.positions.size());
    shape.positions.push_back(glm::vec3(t.p0));
    shape.positions.push_back(glm::vec3(t.p1));
    shape.positions.push_back(glm::vec3(t.p2));
    shape.triangles.push_back({base, base + 1, base + 2});
  }
  return shape;
}

Scene sceneOfShapes(std::vector<Shape> shapes) {
  Scene scene;
  scene.materials.push_back({});
  scene.shapes = std::move(shapes);
  scene.pointLights.push_back({"light", glm::vec3(0.0f, 0.0f, 50.0f), 1.0f});
  return scene;
}

}  // namespace vktg::test
