#include <algorithm>
#include <optional>
#include <stdexcept>

#include "render/frame_uniforms.h"
#include "render/pass_pipelines.h"
#include "support/gpu_context.h"
#include "support/gpu_test.h"

namespace vktg::test {

std::vector<uint32_t> runKernelWords(const std::string& kernel, const std::vector<uint32_t>& input,
                                     size_t outputWords, uint32_t invocations, const Scene* scene,
                                     uint32_t ellipsoidSelection, const std::vector<gpu::GpuEdge>* edges) {
  VulkanContext& context = testContext();
  PassPipelines pipelines(context, kTestShaderRegistry);
  Buffer dummy(context, 256, MemoryKind::Device, "test.dummy");
  Buffer in(context, std::max<size_t>(input.size() * 4, 16), MemoryKind::Device, "test.in");
  in.upload(context, input.data(), input.size() * 4);
  Buffer out(context, std::max<size_t>(outputWords * 4, 16), MemoryKind::Device, "test.out");
  std::vector<uint32_t> zeros(outputWords, 0);
  out.upload(context, zeros.data(), zeros.size() * 4);

  BindingTable table;
  table.set(gpu::kBindingTestIn, in);
  table.set(gpu::kBindingTestOut, out);
  std::optional<PreparedScene> prepared;
  std::optional<GpuScene> gpuScene;
  Buffer frameBuffer(context, sizeof(gpu::FrameUniforms), MemoryKind::Device, "test.frame");
  gpu::FrameUniforms frame{};
  frame.chunkShift = glm::uvec4(31, 31, 31, 0);
  if (scene) {
    prepared.emplace(prepareScene(*scene));
    gpuScene.emplace(context, *prepared);
    table.setScene(*gpuScene);
    frame = sceneFrameUniforms(scene->camera, scene->render, *prepared, *gpuScene);
    setGateUniforms(frame, scene->gate, true);
  }
  std::optional<Buffer> edgeBuffer;
  if (edges && !edges->empty()) {
    edgeBuffer.emplace(context, edges->size() * sizeof(gpu::GpuEdge), MemoryKind::Device, "test.edges");
    edgeBuffer->upload(context, edges->data(), edges->size() * sizeof(gpu::GpuEdge));
    table.set(gpu::kBindingEdges, *edgeBuffer);
    frame.edgeInfo.x = uint32_t(edges->size());
  }
  frameBuffer.upload(context, &frame, sizeof frame);
  table.set(gpu::kBindingFrame, frameBuffer);
  DescriptorSet set(context, pipelines, table, dummy);

  SpecValues spec{};
  spec[gpu::kSpecMaterialMask] = 7;
  spec[gpu::kSpecLightMask] = 3;
  spec[gpu::kSpecEllipsoidSelection] = ellipsoidSelection;
  if (scene) {
    // Scene loads and traversal as the renderer runs them on this device.
    spec[gpu::kSpecSceneTexels] = gpuScene->texels() ? 1u : 0u;
    spec[gpu::kSpecWideBvh] = gpuScene->wideBvh() ? 1u : 0u;
    spec[gpu::kSpecGateType] = uint32_t(scene->gate.type);
    spec[gpu::kSpecCameraType] = uint32_t(scene->camera.type);
  }
  VkPipeline pipeline = pipelines.get(kernel, spec);
  CommandBuffer cmd(context, "test " + kernel);
  cmd.begin();
  vkCmdBindPipeline(cmd.get(), VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  VkDescriptorSet ds = set.get();
  vkCmdBindDescriptorSets(cmd.get(), VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.layout(), 0, 1, &ds, 0, nullptr);
  uint32_t push[4] = {invocations, 0, 0, 0};
  vkCmdPushConstants(cmd.get(), pipelines.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
  uint32_t groups = (invocations + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize;
  if (groups > context.properties().limits.maxComputeWorkGroupCount[0])
    throw std::runtime_error("runKernelWords: too many invocations for one dispatch");
  vkCmdDispatch(cmd.get(), groups, 1, 1);
  cmd.end();
  context.submitAndWait(cmd.get());
  std::vector<uint32_t> result(outputWords);
  out.download(context, result.data(), outputWords * 4);
  return result;
}

}  // namespace vktg::test
