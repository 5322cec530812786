#include "support/test_gates.h"

namespace vktg::test {

Gate gaussianGate(double mu, double sigma, bool normalize) {
  Gate g;
  g.type = GateType::Gaussian;
  g.mu = mu;
  g.sigma = sigma;
  g.normalize = normalize;
  return g;
}

std::vector<GateCase> representativeGates() {
  Gate box, tgauss, bins;
  box.type = GateType::Box;
  box.a = 3.0;
  box.b = 5.5;
  tgauss.type = GateType::TruncatedGaussian;
  tgauss.mu = 4.0;
  tgauss.sigma = 0.5;
  tgauss.a = 3.5;
  tgauss.b = 5.0;
  bins.type = GateType::Bins;
  bins.binStart = 3.0;
  bins.binWidth = 0.25;
  bins.binCount = 8;
  return {{"gaussian", gaussianGate(4.25, 0.125)},
          {"gaussian_normalised", gaussianGate(4.25, 0.125, true)},
          {"box", box},
          {"truncated_gaussian", tgauss},
          {"bins", bins}};
}

Scene sceneWithGate(const Gate& gate) {
  Scene scene;
  scene.materials.push_back({});
  Shape tri;
  tri.name = "tri";
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  scene.shapes.push_back(tri);
  scene.pointLights.push_back({"light", glm::vec3(0, 0, 2), 1.0f});
  scene.gate = gate;
  return scene;
}

}  // namespace vktg::test
