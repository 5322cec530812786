// Memory stays flat over many renders of one scene. An optimisation renders the same scene
// thousands of times with new seeds and parameters; each render allocates its own frame buffers and
// frees them. A driver may still keep state per render: lavapipe compiles a shader variant for
// every distinct set of uniform-buffer values its branches read (it inlines them as constants) and
// keeps every variant, so the per-render frame block, read as a uniform buffer, cost it one variant
// per render: 4-8 MB each, until `vktg optimize` ran out of memory on a confocal scan. The frame block
// is therefore a storage buffer (shaders/lib/scene_bindings.glsl), which no driver specialises on.
//
// The test renders a point sensor's transient (primal, then the edge term's forward lanes, where
// the growth was largest) with 12 seeds after a warm-up and bounds the growth of the resident set.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <unistd.h>

#include "vk/memory_arena.h"
#include "vk/memory_guard.h"
#include "render/memory_preflight.h"
#include "support/gpu_context.h"
#include "support/render_test.h"
#include "support/scoped_env.h"
#include "vktg/error.h"
#include "vktg/parameters.h"

namespace vktg::test {
namespace {

// Resident set size of this process in bytes (/proc/self/statm counts pages).
uint64_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

void renderOnce(const Scene& scene, uint32_t seed, bool edgeLanes) {
  Scene s = scene;
  s.render.seed = seed;
  RenderOptions options;
  if (edgeLanes) {
    options.derivativeLanes = bindParameters(s, {"h27", "h28", "h35", "h36"});
    options.term = Term::Edge;
    s.render.spp = 1024;
  }
  const RenderResult r = renderInTest(s, options);
  ASSERT_EQ(r.stats.nonFinite, 0u);
}

// AddressSanitizer holds freed blocks in its quarantine (256 MiB by default) instead of reusing
// them, so under it the resident set measures the sanitizer, not vktg.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

TEST(RenderMemory, ManyRendersOfOneSceneKeepTheResidentSetFlat) {
  if (kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's quarantine keeps freed memory resident";
  const Scene scene = loadScene(std::filesystem::path(VKTG_SOURCE_DIR) / "tests/data/point_sensor_heightfield.json");
  // Warm-up: pipelines, the pipeline cache and the driver's own pools reach their working size.
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    renderOnce(scene, seed, false);
    renderOnce(scene, seed, true);
  }
  const uint64_t before = residentBytes();
  constexpr uint32_t kRenders = 12;
  for (uint32_t seed = 100; seed < 100 + kRenders; ++seed) {
    renderOnce(scene, seed, false);
    renderOnce(scene, seed, true);
  }
  const double growthMiB = (double(residentBytes()) - double(before)) / double(1 << 20);
  std::printf("  resident set grew %.1f MiB over %u pairs of renders\n", growthMiB, kRenders);
  // Measured: 0-1 MiB with the frame block in a storage buffer; 63 MiB when it was a uniform
  // buffer. 24 MiB leaves room for allocator noise and stays far below one variant per render.
  EXPECT_LT(growthMiB, 24.0);
}

// Without --mem a render sizes its batches by the device: 512 MiB on a CPU device, a quarter of a
// GPU's memory (512 MiB to 4 GiB) there, where fewer, larger batches pay fewer per-batch dispatches.
TEST(RenderMemory, DefaultBudgetFollowsTheDevice) {
  const VulkanContext& context = testContext();
  const uint64_t budget = defaultMemoryBudget(context), device = context.report().deviceLocalBytes;
  if (context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
    EXPECT_EQ(budget, 512ull << 20);
  } else {
    EXPECT_GE(budget, 512ull << 20);
    EXPECT_LE(budget, 4096ull << 20);
    EXPECT_LE(budget, std::max<uint64_t>(512ull << 20, device / 4));
  }
}

// The budget (--mem, or the default) is what a render chooses to spend, its film and wavefront
// state; the scene is the input's own size and counts against the device only. So a mesh larger
// than the budget still renders (a million-height heightfield's scene and edge list take 547 MiB,
// beyond a CPU device's default 512), with the budget left for the film and batches, while a film
// beyond the budget is refused whatever the scene.
TEST(RenderMemory, SceneCountsAgainstTheDeviceNotTheBudget) {
  const VulkanContext& context = testContext();
  const uint64_t device = context.report().deviceLocalBytes;
  ASSERT_GT(device, 700ull << 20) << "the test needs a device that holds a 600 MiB scene";
  RenderMemory need;
  need.film = 1ull << 20;
  need.smallestBatch = 1ull << 20;
  need.scene = 600ull << 20;
  need.filmShape = "test";
  EXPECT_EQ(checkRenderMemory(context, need, 16ull << 20), 16ull << 20);
  EXPECT_EQ(checkRenderMemory(context, need, 0), std::min(defaultMemoryBudget(context), device - need.scene));
  need.film = 20ull << 20;
  EXPECT_THROW(checkRenderMemory(context, need, 16ull << 20), Error);
  need.film = 1ull << 20;
  need.scene = device;
  EXPECT_THROW(checkRenderMemory(context, need, 0), Error);
}

// Device memory that the host cannot read directly (unmapped, as VKTG_DEVICE_MEMORY=staged forces
// on any device, or mapped uncached on a GPU) goes both ways through staging copies: whole, from an
// offset, and through a staging buffer the caller keeps.
TEST(RenderMemory, StagedDeviceMemoryRoundTrips) {
  const VulkanContext& context = testContext();
  test::ScopedEnv staged("VKTG_DEVICE_MEMORY", "staged");
  Buffer buffer(context, 1 << 20, MemoryKind::Device, "staged");
  ASSERT_EQ(buffer.mapped(), nullptr);
  ASSERT_FALSE(buffer.hostReadable());
  std::vector<uint32_t> data(buffer.size() / 4);
  for (size_t i = 0; i < data.size(); ++i) data[i] = uint32_t(i * 2654435761u);
  buffer.upload(context, data.data(), buffer.size());
  std::vector<uint32_t> back(data.size());
  buffer.download(context, back.data(), buffer.size());
  EXPECT_EQ(back, data);
  Buffer keep(context, 1 << 19, MemoryKind::Readback, "staging kept");
  ASSERT_TRUE(keep.hostReadable());
  std::vector<uint32_t> part(1000);
  buffer.download(context, part.data(), part.size() * 4, 4 * 5000, &keep);
  EXPECT_TRUE(std::equal(part.begin(), part.end(), data.begin() + 5000));
  std::vector<uint32_t> whole(data.size());
  buffer.download(context, whole.data(), buffer.size(), 0, &keep);  // too small to keep: a fresh one
  EXPECT_EQ(whole, data);
}

// Successive sets of per-render buffers share one block: it is allocated again only to grow, and
// each set reads back what it wrote at its own offsets (the buffers do not overlap one another).
TEST(RenderMemory, ArenaBindsEachSetIntoOneBlockThatOnlyGrows) {
  const VulkanContext& context = testContext();
  MemoryArena arena(context, "test arena");
  auto roundTrip = [&](std::vector<Buffer>& set) {
    std::vector<Buffer*> pointers;
    for (Buffer& b : set) pointers.push_back(&b);
    arena.bind(pointers);
    for (size_t i = 0; i < set.size(); ++i) {
      std::vector<uint32_t> data(set[i].size() / 4, uint32_t(0x1000 * (i + 1)));
      set[i].upload(context, data.data(), set[i].size());
    }
    for (size_t i = 0; i < set.size(); ++i) {
      std::vector<uint32_t> back(set[i].size() / 4);
      set[i].download(context, back.data(), set[i].size());
      for (uint32_t v : back) ASSERT_EQ(v, uint32_t(0x1000 * (i + 1))) << set[i].name();
    }
  };
  auto makeSet = [&](std::initializer_list<VkDeviceSize> sizes) {
    std::vector<Buffer> set;
    for (VkDeviceSize size : sizes)
      set.emplace_back(context, size, MemoryKind::Device, "set" + std::to_string(set.size()), Binding::Arena);
    return set;
  };
  {
    std::vector<Buffer> large = makeSet({1 << 20, 4096, 3 << 18});
    roundTrip(large);
  }
  EXPECT_EQ(arena.allocations(), 1u);
  const VkDeviceSize capacity = arena.capacity();
  EXPECT_GE(capacity, VkDeviceSize((1 << 20) + 4096 + (3 << 18)));
  {
    std::vector<Buffer> smaller = makeSet({256, 1 << 20});
    roundTrip(smaller);
  }
  EXPECT_EQ(arena.allocations(), 1u);
  EXPECT_EQ(arena.capacity(), capacity);
  {
    std::vector<Buffer> larger = makeSet({4 << 20, 1024});
    roundTrip(larger);
  }
  EXPECT_EQ(arena.allocations(), 2u);
  EXPECT_GE(arena.capacity(), VkDeviceSize((4 << 20) + 1024));
  // A bound buffer cannot be bound twice.
  std::vector<Buffer> once = makeSet({64});
  arena.bind({&once[0]});
  EXPECT_THROW(arena.bind({&once[0]}), Error);
}

// With VKTG_GUARD_MEMORY=1 (on in the tests) every buffer mapped cached, alone or in an arena, has a guard
// after its end, checked after each submission: a write past a buffer's end fails the next
// submission and names the buffer.
TEST(RenderMemory, AWritePastABuffersEndFailsTheNextSubmission) {
  const VulkanContext& context = testContext();  // applies the test environment first
  ASSERT_TRUE(memoryGuardsOn()) << "the tests run with VKTG_GUARD_MEMORY=1";
  Buffer own(context, 100, MemoryKind::Device, "own memory");
  MemoryArena arena(context, "guard arena");
  std::vector<Buffer> set;
  set.emplace_back(context, 64, MemoryKind::Device, "first in the arena", Binding::Arena);
  set.emplace_back(context, 64, MemoryKind::Device, "second in the arena", Binding::Arena);
  arena.bind({&set[0], &set[1]});
  if (!own.hostReadable() || !set[0].hostReadable())
    GTEST_SKIP() << "this device's memory is not mapped cached: it has no guards";
  auto submit = [&] {
    CommandBuffer cmd(context, "guard test");
    cmd.begin();
    cmd.end();
    context.submitAndWait(cmd.get());
  };
  for (Buffer* b : {&own, &set[0], &set[1]}) {
    EXPECT_NO_THROW(submit());
    char* past = static_cast<char*>(b->mapped()) + b->size();
    *past ^= 0x40;
    try {
      submit();
      ADD_FAILURE() << "nothing caught the write past '" << b->name() << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("'" + b->name() + "'"), std::string::npos) << e.what();
    }
    *past ^= 0x40;
  }
  EXPECT_NO_THROW(submit());
}

}  // namespace
}  // namespace vktg::test
