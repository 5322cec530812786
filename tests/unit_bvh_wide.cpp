// The binary BVH collapsed to 4 children per node (collapseBvh, the tree CPU devices traverse):
// the same leaves in the same order, every child box the binary tree's box for that subtree, and
// no tree the layout cannot hold. (That the traversal finds the same hits is tests/gpu_bvh.cpp's.)
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <functional>
#include <random>

#include "vktg/bvh.h"

namespace vktg {
namespace {

using Soup = std::vector<BvhTriangle>;

uint32_t word(float f) { return std::bit_cast<uint32_t>(f); }

Soup randomSoup(std::mt19937& rng, size_t n, float extent, float size) {
  std::uniform_real_distribution<float> centre(-extent, extent), offset(-size, size);
  Soup soup(n);
  for (BvhTriangle& t : soup) {
    glm::vec3 c(centre(rng), centre(rng), centre(rng));
    auto corner = [&] { return c + glm::vec3(offset(rng), offset(rng), offset(rng)); };
    t = {corner(), corner(), corner()};
  }
  return soup;
}

// The box the binary tree keeps for the child at `source` (2 * parent + side).
void sourceBox(const Bvh& bvh, uint32_t source, glm::vec3& lo, glm::vec3& hi) {
  const gpu::GpuBvhNode& n = bvh.nodes.at(source / 2);
  lo = glm::vec3(source % 2 ? n.rightMinCount : n.leftMinLeftIndex);
  hi = glm::vec3(source % 2 ? n.rightMaxFirst : n.leftMaxRightIndex);
}

// Every wide node is reached once, leaves cover leaf order once in ascending order, inner nodes
// (but a root over a single leaf) have at least two children and fewer than four only where every
// child is a leaf (the collapse adopts grandchildren while it can), boxes are the binary tree's,
// and the deepest near-first stack fits. Returns the number of leaves; `absorbed` counts the binary
// inner nodes the wide nodes stand for (a node of c children absorbs c - 1 of them).
size_t expectSoundCollapse(const Bvh& bvh, const std::vector<gpu::GpuWideBvhNode>& wide, size_t triangles,
                           size_t* absorbed = nullptr) {
  std::vector<int> reached(wide.size(), 0);
  uint32_t nextTriangle = 0;
  size_t leaves = 0, inner = 0;
  std::function<uint32_t(uint32_t)> walk = [&](uint32_t index) -> uint32_t {
    EXPECT_LT(index, wide.size());
    if (index >= wide.size()) return 0;
    ++reached[index];
    const gpu::GpuWideBvhNode& node = wide[index];
    uint32_t used = 0, deepest = 0;
    bool innerChild = false;
    for (int k = 0; k < 4; ++k) {
      const uint32_t child = node.child[k];
      if (child == gpu::kWideBvhEmpty) {
        EXPECT_GT(node.loX[k], node.hiX[k]) << "an unused slot's box must be empty";
        continue;
      }
      EXPECT_EQ(used, uint32_t(k)) << "used slots come first";
      ++used;
      if (node.source[k] != gpu::kWideBvhEmpty) {
        glm::vec3 lo, hi;
        sourceBox(bvh, node.source[k], lo, hi);
        const glm::vec3 wlo(node.loX[k], node.loY[k], node.loZ[k]), whi(node.hiX[k], node.hiY[k], node.hiZ[k]);
        EXPECT_EQ(std::memcmp(&lo, &wlo, sizeof lo), 0) << "node " << index << " slot " << k;
        EXPECT_EQ(std::memcmp(&hi, &whi, sizeof hi), 0) << "node " << index << " slot " << k;
      } else {
        EXPECT_EQ(index, 0u) << "only the root's single leaf has no binary parent";
      }
      if (child & gpu::kWideBvhLeaf) {
        ++leaves;
        const uint32_t first = (child & ~gpu::kWideBvhLeaf) >> gpu::kWideBvhFirstShift;
        const uint32_t count = child & gpu::kWideBvhMaxLeafCount;
        EXPECT_EQ(first, nextTriangle) << "leaves in leaf order";
        EXPECT_GT(count, 0u);
        nextTriangle = first + count;
      } else {
        innerChild = true;
        deepest = std::max(deepest, walk(child));
      }
    }
    EXPECT_GE(used, index == 0 ? 1u : 2u) << "node " << index;
    if (used < 4) EXPECT_FALSE(innerChild) << "node " << index << " could have adopted a grandchild";
    inner += used - 1;
    return used - 1 + deepest;
  };
  const uint32_t need = walk(0);
  if (absorbed) *absorbed = inner;
  EXPECT_EQ(nextTriangle, triangles) << "the leaves must cover every triangle";
  for (size_t i = 0; i < reached.size(); ++i) EXPECT_EQ(reached[i], 1) << "wide node " << i;
  EXPECT_LE(need, kBvhStackSize);
  return leaves;
}

TEST(BvhCollapse, RandomSoupsKeepLeavesAndBoxes) {
  std::mt19937 rng(17);
  for (size_t n : {2, 3, 9, 100, 5000}) {
    for (uint32_t leaf : {1u, 4u, 8u}) {
      SCOPED_TRACE(std::to_string(n) + " triangles, leaves of " + std::to_string(leaf));
      const Soup soup = randomSoup(rng, n, 5.0f, 0.5f);
      BvhBuildOptions options;
      options.maxLeafSize = leaf;
      const Bvh bvh = buildBvh(soup, options);
      const std::vector<gpu::GpuWideBvhNode> wide = collapseBvh(bvh);
      ASSERT_FALSE(wide.empty());
      size_t binaryLeaves = 0, absorbed = 0;
      for (const gpu::GpuBvhNode& node : bvh.nodes) binaryLeaves += word(node.rightMinCount.w) > 0;
      EXPECT_EQ(expectSoundCollapse(bvh, wide, n, &absorbed), binaryLeaves);
      // Each binary inner node stands inside exactly one wide node.
      EXPECT_EQ(absorbed, bvh.nodes.size() - binaryLeaves);
    }
  }
}

TEST(BvhCollapse, SingleLeafRootGetsAnUnboundedSlot) {
  const Soup soup{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  const Bvh bvh = buildBvh(soup);
  ASSERT_GT(word(bvh.nodes[0].rightMinCount.w), 0u) << "one triangle should make a root leaf";
  const std::vector<gpu::GpuWideBvhNode> wide = collapseBvh(bvh);
  ASSERT_EQ(wide.size(), 1u);
  EXPECT_EQ(wide[0].child[0], gpu::kWideBvhLeaf | 1u);
  EXPECT_LT(wide[0].loX[0], -1e38f);
  EXPECT_GT(wide[0].hiX[0], 1e38f);
  expectSoundCollapse(bvh, wide, soup.size());
}

TEST(BvhCollapse, LeavesTheLayoutCannotHoldGiveNoTree) {
  // Coincident centroids make one leaf of every triangle: the count field holds up to 63.
  for (uint32_t count : {gpu::kWideBvhMaxLeafCount, gpu::kWideBvhMaxLeafCount + 1}) {
    Soup soup(count, BvhTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    soup.push_back({{5, 5, 5}, {6, 5, 5}, {5, 6, 5}});
    const Bvh bvh = buildBvh(soup);
    EXPECT_EQ(collapseBvh(bvh).empty(), count > gpu::kWideBvhMaxLeafCount) << count << " coincident triangles";
  }
  EXPECT_TRUE(collapseBvh(Bvh{}).empty());
  EXPECT_TRUE(collapseBvh(buildBvh(Soup{})).empty()) << "an empty scene keeps the binary traversal";
}

}  // namespace
}  // namespace vktg
