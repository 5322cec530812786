// Across devices a render is not bit-identical (a GPU compiler contracts and reorders float
// arithmetic, docs/precision.md) but must agree within statistical error: the same scene rendered
// on a GPU and on lavapipe, independent seeds, every pixel z-tested. Runs only where both are
// visible, i.e. under `VKTG_TEST_DEVICE=gpu tools/test` on a machine with a GPU (the test
// environment then keeps every installed driver); plain ctest sees lavapipe alone and skips it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>

#include "render/renderer.h"
#include "support/gpu_context.h"
#include "support/render_test.h"
#include "support/test_scenes.h"
#include "vktg/gate.h"

namespace vktg::test {
namespace {

constexpr double kZ = 3.29;  // two-sided alpha 1e-3 for the image means

std::optional<uint32_t> firstUsable(bool cpu) {
  for (const DeviceReport& d : VulkanContext::listDevices())
    if (d.usable && (d.type == "cpu") == cpu) return d.index;
  return std::nullopt;
}

RenderResult renderOn(uint32_t device, const Scene& scene) {
  ContextOptions options = contextOptionsFromEnvironment();
  options.device = std::to_string(device);
  VulkanContext context(options);
  RenderResult result;
  {
    Renderer renderer(context);
    RenderOptions ro;
    ro.nee = NeeMode::Standard;
    result = renderer.render(scene, ro);
  }
  for (const std::string& message : context.takeValidationMessages()) ADD_FAILURE() << "validation: " << message;
  return result;
}

TEST(RenderCrossDevice, GpuAndLavapipeAgreeWithinNoise) {
  testContext();  // applies the test environment (which drivers are visible)
  const std::optional<uint32_t> gpu = firstUsable(false), cpu = firstUsable(true);
  if (!gpu || !cpu) GTEST_SKIP() << "needs a GPU and lavapipe side by side (VKTG_TEST_DEVICE=gpu tools/test)";
  Scene scene = cornellScene(16, 6.0, 2.0, false);
  scene.render.maxDepth = 4;
  scene.render.spp = 512;
  scene.gate = parseGateSpec("box:3.5,5.5");
  scene.render.seed = 1;
  const RenderResult a = renderOn(*gpu, scene);
  scene.render.seed = 2;
  const RenderResult b = renderOn(*cpu, scene);
  const auto& am = a.mean.layers.at(0).pixels;
  const auto& bm = b.mean.layers.at(0).pixels;
  const ZTestResult z = zTest(am, a.variance.layers.at(0).pixels, bm, b.variance.layers.at(0).pixels);
  EXPECT_EQ(z.rejected, 0u) << z.rejected << " of " << z.tested << " pixels differ; worst " << z.worst;
  EXPECT_LE(z.untestable, am.size() / 20);
  const ImageMean ma = imageMean(am, a.variance.layers.at(0).pixels), mb = imageMean(bm, b.variance.layers.at(0).pixels);
  const double se = std::hypot(ma.standardError, mb.standardError);
  EXPECT_LT(std::abs(ma.mean - mb.mean), kZ * se) << ma.mean << " (GPU) vs " << mb.mean << " (lavapipe)";
  std::printf("  GPU %.6g vs lavapipe %.6g (z = %.2f), worst pixel %s\n", ma.mean, mb.mean,
              std::abs(ma.mean - mb.mean) / se, z.worst.c_str());
}

}  // namespace
}  // namespace vktg::test
