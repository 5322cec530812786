// The GPU test harness itself: a kernel runs on the test device and returns what it computed.
#include <gtest/gtest.h>

#include "support/gpu_test.h"

namespace vktg::test {

TEST(GpuHarness, KernelSeesInputsAndScene) {
  Scene scene;
  scene.materials.push_back({});
  Shape quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  quad.emission = 1.0f;
  scene.shapes.push_back(quad);
  std::vector<float> input(1000);
  for (size_t i = 0; i < input.size(); ++i) input[i] = float(i) * 0.5f;
  struct Out { float square; uint32_t triangles; };
  auto out = runKernel<Out>("harness_smoke", input, input.size(), uint32_t(input.size()), &scene);
  for (size_t i = 0; i < input.size(); ++i) {
    ASSERT_EQ(out[i].square, input[i] * input[i]) << i;
    ASSERT_EQ(out[i].triangles, 2u);
  }
}

}  // namespace vktg::test
