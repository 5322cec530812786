#include "bench/bench_scenes.h"

#include <cmath>
#include <vector>

#include "bench/bench_common.h"
#include "scene/primitives.h"

namespace vktg {

Scene tessellatedRoom(uint32_t n, uint32_t resolution) {
  Scene scene = defaultScene();
  std::erase_if(scene.shapes, [](const Shape& s) { return s.name == "short_box" || s.name == "tall_box"; });
  std::vector<float> heights(size_t(n) * n);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), z = double(j) / (n - 1);
      heights[size_t(j) * n + i] =
          float(0.1 + 0.08 * std::sin(9.0 * x) * std::cos(7.0 * z) + 0.03 * std::sin(31.0 * x * z));
    }
  TriangleMesh mesh = makeHeightfield(n, n, 1.8f, 1.8f, heights);
  Shape shape;
  shape.name = "terrain";
  shape.material = 2;  // white
  shape.positions = std::move(mesh.positions);
  shape.triangles = std::move(mesh.triangles);
  shape.grid = {n, n};
  scene.shapes.push_back(std::move(shape));
  scene.camera.width = scene.camera.height = resolution;
  scene.gate = gaussianGate(7.0, 0.07);
  return scene;
}

}  // namespace vktg
