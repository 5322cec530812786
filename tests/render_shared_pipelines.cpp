// Every renderer and scene update on one context uses the context's pipelines: a process that
// renders many scenes or starts many optimisations (a Python session, a benchmark, an optimisation
// resumed in-process) compiles each pipeline variant once. On lavapipe a render's pipelines take
// seconds to make, most of a small render's time. What is checked: a second renderer of the same
// scene creates no pipeline and renders the same bits, and the context keeps one object per key.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "render/device_scene.h"
#include "render/pass_pipelines.h"
#include "render/renderer.h"
#include "support/gpu_context.h"
#include "vktg/scene.h"
#include "vktg/shader_registry.h"

namespace vktg::test {
namespace {

RenderResult renderWithANewRenderer(VulkanContext& context, const Scene& scene) {
  Renderer renderer(context);
  DeviceScene device(context, scene);
  RenderSetup setup = RenderSetup::of(scene);
  return renderer.render(device, setup, {});
}

TEST(RenderSharedPipelines, ASecondRendererCreatesNoPipelineAndRendersTheSameBits) {
  VulkanContext& context = testContext();
  const Scene scene = loadScene(std::filesystem::path(VKTG_SOURCE_DIR) / "tests/data/point_sensor_heightfield.json");
  const std::shared_ptr<PassPipelines> pipelines =
      PassPipelines::shared(context, kShaderRegistry, defaultPipelineCacheFile(context));
  const RenderResult first = renderWithANewRenderer(context, scene);
  const size_t afterFirst = pipelines->size();
  // The render's pipelines live in the shared object (with renderers of their own it stays empty;
  // not "more than before", which a repeated run of this test would already have filled).
  EXPECT_GT(afterFirst, 0u);
  const RenderResult second = renderWithANewRenderer(context, scene);
  EXPECT_EQ(pipelines->size(), afterFirst);
  ASSERT_EQ(first.mean.layers.size(), second.mean.layers.size());
  double total = 0;
  for (size_t l = 0; l < first.mean.layers.size(); ++l) {
    EXPECT_EQ(first.mean.layers[l].pixels, second.mean.layers[l].pixels) << "layer " << l;
    for (float x : first.mean.layers[l].pixels) total += x;
  }
  EXPECT_GT(total, 0.0);  // equal zeros would prove nothing
}

TEST(RenderSharedPipelines, OneObjectPerKeyMadeOnce) {
  VulkanContext& context = testContext();
  int made = 0;
  auto make = [&] {
    ++made;
    return std::make_shared<int>(made);
  };
  static int run = 0;  // keys of their own in each repetition of this test
  const std::string one = "test one " + std::to_string(++run), two = "test two " + std::to_string(run);
  const std::shared_ptr<int> a = context.shared<int>(one, make), b = context.shared<int>(one, make);
  const std::shared_ptr<int> c = context.shared<int>(two, make);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(made, 2);
  // The scene-update passes' layout has its own object (no cache file: nothing written to disk).
  const std::filesystem::path file;
  EXPECT_NE(PassPipelines::shared(context, kShaderRegistry, file),
            PassPipelines::shared(context, kShaderRegistry, file, gpu::kUpdateBindingCount));
  EXPECT_EQ(PassPipelines::shared(context, kShaderRegistry, file), PassPipelines::shared(context, kShaderRegistry, file));
}

}  // namespace
}  // namespace vktg::test
