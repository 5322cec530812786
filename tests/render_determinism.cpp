// Reproducibility: the same scene and seed give the same image bit for bit on the same device,
// whatever the batch size (the memory budget) and from one run to the next. The film adds each
// pixel's paths in sample order with compensated sums (shaders/accumulate.comp), so batching
// changes nothing; a path's accumulator receives at most one contribution per dispatch with
// standard NEE. (Ellipsoidal and MIS NEE queue several connections per path whose float atomics
// may land in any order, and the splatted gradient terms add into the film with atomics: their
// last bits may depend on the device's scheduling.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "support/gpu_context.h"
#include "support/render_test.h"
#include "support/scoped_env.h"
#include "support/test_scenes.h"
#include "scene/primitives.h"
#include "vktg/gate.h"
#include "vktg/parameters.h"

namespace vktg::test {
namespace {

Scene transientCornell() {
  Scene scene = cornellScene(12, 6.0, 2.0, false);
  scene.render.maxDepth = 4;
  scene.render.rouletteDepth = 2;
  scene.render.spp = 256;
  scene.render.seed = 77;
  scene.gate = parseGateSpec("bins:3,0.5,8");
  Parameter p;
  p.name = "left_x", p.kind = ParameterKind::Translate, p.target = "left", p.axis = {1.0f, 0.0f, 0.0f};
  scene.parameters.push_back(p);
  return scene;
}

void expectBitIdentical(const ImageSet& a, const ImageSet& b, const std::string& what) {
  ASSERT_EQ(a.layers.size(), b.layers.size()) << what;
  for (size_t k = 0; k < a.layers.size(); ++k) {
    const std::vector<float>& x = a.layers[k].pixels;
    const std::vector<float>& y = b.layers[k].pixels;
    ASSERT_EQ(x.size(), y.size()) << what;
    size_t differing = 0;
    for (size_t i = 0; i < x.size(); ++i) differing += std::memcmp(&x[i], &y[i], sizeof(float)) != 0;
    EXPECT_EQ(differing, 0u) << what << ", layer " << a.layers[k].name << ": " << differing << " of " << x.size()
                             << " pixels differ";
  }
}

// The image and every derivative image of two renders, bit for bit.
void expectSameImages(const RenderResult& a, const RenderResult& b) {
  expectBitIdentical(a.mean, b.mean, "image");
  ASSERT_EQ(a.derivatives.size(), b.derivatives.size());
  for (size_t k = 0; k < a.derivatives.size(); ++k) expectBitIdentical(a.derivatives[k], b.derivatives[k], "derivative");
}

RenderResult renderWithBudget(const Scene& scene, uint64_t budget, bool derivative) {
  RenderOptions options;
  options.nee = NeeMode::Standard;
  options.memoryBudget = budget;
  if (derivative) options.derivativeLanes = bindParameters(scene, {"left_x"});
  return renderInTest(scene, options);
}

TEST(RenderDeterminism, SameSeedSameBitsAtAnyBatchSize) {
  const Scene scene = transientCornell();
  for (bool derivative : {false, true}) {
    SCOPED_TRACE(derivative ? "interior derivative lanes" : "image");
    RenderResult whole = renderWithBudget(scene, 512ull << 20, derivative);
    RenderResult again = renderWithBudget(scene, 512ull << 20, derivative);
    RenderResult batched = renderWithBudget(scene, 2ull << 20, derivative);
    ASSERT_EQ(whole.stats.batches, 1u) << "the large budget should hold the whole render";
    ASSERT_GT(batched.stats.batches, 3u) << "the small budget should split the render into batches";
    std::printf("  %s: 1 batch of %u paths vs %u batches of %u\n", derivative ? "derivatives" : "image",
                whole.stats.batchSize, batched.stats.batches, batched.stats.batchSize);
    expectBitIdentical(whole.mean, again.mean, "image, run to run");
    expectBitIdentical(whole.mean, batched.mean, "image, batched");
    expectBitIdentical(whole.variance, batched.variance, "variance, batched");
    for (size_t k = 0; k < whole.derivatives.size(); ++k) {
      expectBitIdentical(whole.derivatives[k], again.derivatives[k], "derivative, run to run");
      expectBitIdentical(whole.derivatives[k], batched.derivatives[k], "derivative, batched");
      expectBitIdentical(whole.derivativeVariances[k], batched.derivativeVariances[k], "derivative variance, batched");
    }
  }
}

RenderResult renderUnder(const Scene& scene, bool derivative, const char* variable, const char* value,
                         NeeMode nee = NeeMode::Standard) {
  RenderOptions options;
  options.nee = nee;
  if (derivative) options.derivativeLanes = bindParameters(scene, {"left_x"});
  ScopedEnv env(variable, value);
  Renderer renderer(testContext());  // its own film, allocated under the variable
  return renderer.render(scene, options);
}

// Buffers larger than a chunk (VKTG_MAX_CHUNK_BYTES caps it on any device) are read through the
// general accessors; every other render through the single-chunk ones (kSpecSingleChunk). Both
// must give the same bits.
TEST(RenderDeterminism, BuffersSplitIntoChunksGiveTheSameBits) {
  Scene filmSplit = transientCornell();  // 12 x 12 pixels x 8 bins: the film takes several 16 KiB chunks
  Scene sceneSplit = transientCornell();  // 2 x 2 pixels: triangles and BVH nodes take several 1 KiB chunks
  sceneSplit.camera.width = sceneSplit.camera.height = 2;
  for (auto [scene, cap] : {std::pair{&filmSplit, "16384"}, std::pair{&sceneSplit, "1024"}}) {
    for (bool derivative : {false, true}) {
      SCOPED_TRACE(std::string(derivative ? "derivative lanes" : "image") + ", chunks of at most " + cap + " bytes");
      RenderResult whole = renderWithBudget(*scene, 512ull << 20, derivative);
      ASSERT_EQ(whole.stats.bufferChunks, 1u);
      RenderResult split = renderUnder(*scene, derivative, "VKTG_MAX_CHUNK_BYTES", cap);
      EXPECT_GT(split.stats.bufferChunks, 1u) << "the cap should have split a buffer";
      if (scene == &sceneSplit) EXPECT_FALSE(split.stats.sceneTexels) << "split buffers load through storage buffers";
      expectSameImages(whole, split);
    }
  }
}

// Triangles, BVH nodes, path states and hits load through texel buffers on CPU devices and
// through storage buffers on GPUs (VKTG_SCENE_ACCESS forces either): the same bits both ways.
TEST(RenderDeterminism, TexelAndStorageSceneLoadsGiveTheSameBits) {
  const Scene scene = transientCornell();
  for (bool derivative : {false, true}) {
    SCOPED_TRACE(derivative ? "derivative lanes" : "image");
    RenderResult storage = renderUnder(scene, derivative, "VKTG_SCENE_ACCESS", "storage");
    RenderResult texel = renderUnder(scene, derivative, "VKTG_SCENE_ACCESS", "texel");
    ASSERT_FALSE(storage.stats.sceneTexels || storage.stats.waveTexels);
    ASSERT_TRUE(texel.stats.sceneTexels && texel.stats.waveTexels);
    expectSameImages(storage, texel);
  }
}

// The shadow pass visits only a path's filled connection slots on CPU devices and loops over every
// slot on GPUs (VKTG_SHADOW_SLOTS forces either): the same connections in the same order, so the
// same bits. MIS fills two slots per vertex (a standard and an ellipsoidal connection).
TEST(RenderDeterminism, FilledAndAllShadowSlotLoopsGiveTheSameBits) {
  const Scene scene = transientCornell();
  for (bool derivative : {false, true}) {
    SCOPED_TRACE(derivative ? "derivative lanes" : "image");
    RenderResult all = renderUnder(scene, derivative, "VKTG_SHADOW_SLOTS", "all", NeeMode::Mis);
    RenderResult filled = renderUnder(scene, derivative, "VKTG_SHADOW_SLOTS", "filled", NeeMode::Mis);
    expectSameImages(all, filled);
  }
}

// CPU devices traverse the BVH collapsed to 4 children per node, GPUs the binary one
// (VKTG_BVH_WIDTH forces either): the same hits, so the same bits. A heightfield on the floor
// gives the trees some depth.
TEST(RenderDeterminism, WideAndBinaryBvhGiveTheSameBits) {
  Scene scene = transientCornell();
  const uint32_t n = 24;
  std::vector<float> heights(n * n);
  for (uint32_t i = 0; i < heights.size(); ++i) heights[i] = 0.05f * std::sin(0.7f * float(i % n)) * std::cos(0.9f * float(i / n));
  TriangleMesh mesh = makeHeightfield(n, n, 1.6f, 1.6f, heights);
  Shape floor;
  floor.name = "floor";
  floor.positions = std::move(mesh.positions);
  for (glm::vec3& p : floor.positions) p.y -= 0.9f;
  floor.triangles = std::move(mesh.triangles);
  scene.shapes.push_back(std::move(floor));
  for (bool derivative : {false, true}) {
    SCOPED_TRACE(derivative ? "derivative lanes" : "image");
    RenderResult binary = renderUnder(scene, derivative, "VKTG_BVH_WIDTH", "2");
    RenderResult wide = renderUnder(scene, derivative, "VKTG_BVH_WIDTH", "4");
    ASSERT_FALSE(binary.stats.wideBvh);
    if (!wide.stats.sceneTexels) GTEST_SKIP() << "the wide tree is read through texel views, which this device does not use";
    ASSERT_TRUE(wide.stats.wideBvh);
    expectSameImages(binary, wide);
  }
}

// Device memory is mapped on lavapipe, integrated GPUs and GPUs with a resizable BAR, and reached
// through staging copies elsewhere (VKTG_DEVICE_MEMORY forces either): the same bits both ways.
TEST(RenderDeterminism, MappedAndStagedDeviceMemoryGiveTheSameBits) {
  const Scene scene = transientCornell();
  // Returns the staged render's buffer chunks.
  auto expectSameBits = [&](bool derivative) {
    RenderResult mapped = renderUnder(scene, derivative, "VKTG_DEVICE_MEMORY", "mapped");
    RenderResult staged = renderUnder(scene, derivative, "VKTG_DEVICE_MEMORY", "staged");
    expectSameImages(mapped, staged);
    expectBitIdentical(mapped.variance, staged.variance, "variance");
    return staged.stats.bufferChunks;
  };
  for (bool derivative : {false, true}) {
    SCOPED_TRACE(derivative ? "derivative lanes" : "image");
    expectSameBits(derivative);
  }
  // A film of several chunks goes back a chunk at a time where the host cannot map it; one chunk is
  // copied by the render's last batch (tests/render_round_trips.cpp).
  SCOPED_TRACE("film split into chunks");
  ScopedEnv chunks("VKTG_MAX_CHUNK_BYTES", "16384");
  EXPECT_GT(expectSameBits(false), 1u) << "the cap should have split the film";
}

TEST(RenderDeterminism, DifferentSeedsDiffer) {
  // The control: the comparison above would pass trivially if the seed were ignored.
  Scene scene = transientCornell();
  RenderResult a = renderWithBudget(scene, 512ull << 20, false);
  scene.render.seed += 1;
  RenderResult b = renderWithBudget(scene, 512ull << 20, false);
  size_t differing = 0;
  for (size_t k = 0; k < a.mean.layers.size(); ++k)
    for (size_t i = 0; i < a.mean.layers[k].pixels.size(); ++i)
      differing += a.mean.layers[k].pixels[i] != b.mean.layers[k].pixels[i];
  EXPECT_GT(differing, 100u);
}

}  // namespace
}  // namespace vktg::test
