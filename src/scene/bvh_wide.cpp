// The binary BVH collapsed to 4 children per node for the traversal of CPU devices (kSpecWideBvh).
#include <algorithm>
#include <bit>
#include <cfloat>

#include "vktg/bvh.h"

namespace vktg {
namespace {

uint32_t word(float f) { return std::bit_cast<uint32_t>(f); }

// A child of a wide node: a binary-tree node and the box its parent keeps for it.
struct Slot {
  glm::vec3 lo, hi;
  uint32_t node;    // binary-tree node index
  uint32_t source;  // 2 * parent + side, or kWideBvhEmpty (the root: no parent holds its box)
};

bool isLeaf(const gpu::GpuBvhNode& n) { return word(n.rightMinCount.w) > 0; }

float halfArea(const Slot& s) {
  const glm::vec3 e = glm::max(s.hi - s.lo, glm::vec3(0.0f));
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

class Collapser {
 public:
  explicit Collapser(const Bvh& bvh) : m_bvh(bvh) {}

  // Wide node for the binary subtree under `slots` (1 or 2 of them) at wide depth `depth`; its
  // index, and in `need` the stack entries a near-first traversal of it may hold. False if the
  // layout cannot hold it (or the binary tree is deeper than any buildBvh makes).
  bool collapse(std::vector<Slot> slots, uint32_t depth, uint32_t& index, uint32_t& need) {
    if (depth > kBvhStackSize) return false;
    while (slots.size() < 4) {
      int widest = -1;
      for (size_t i = 0; i < slots.size(); ++i)
        if (!isLeaf(m_bvh.nodes[slots[i].node]) && (widest < 0 || halfArea(slots[i]) > halfArea(slots[size_t(widest)])))
          widest = int(i);
      if (widest < 0) break;
      // Its two children take its place, left then right: leaf order stays ascending.
      const uint32_t parent = slots[size_t(widest)].node;
      const gpu::GpuBvhNode& n = m_bvh.nodes[parent];
      const Slot left{glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex), word(n.leftMinLeftIndex.w), 2 * parent};
      const Slot right{glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst), word(n.leftMaxRightIndex.w), 2 * parent + 1};
      slots[size_t(widest)] = left;
      slots.insert(slots.begin() + widest + 1, right);
    }
    index = uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    gpu::GpuWideBvhNode wide;
    uint32_t deepest = 0;
    for (int k = 0; k < 4; ++k) {
      uint32_t child = gpu::kWideBvhEmpty, source = gpu::kWideBvhEmpty;
      glm::vec3 lo(FLT_MAX), hi(-FLT_MAX);
      if (size_t(k) < slots.size()) {
        const Slot& s = slots[size_t(k)];
        const gpu::GpuBvhNode& n = m_bvh.nodes[s.node];
        lo = s.lo, hi = s.hi, source = s.source;
        if (isLeaf(n)) {
          const uint32_t count = word(n.rightMinCount.w), first = word(n.rightMaxFirst.w);
          if (count > gpu::kWideBvhMaxLeafCount || first > gpu::kWideBvhMaxFirst) return false;
          child = gpu::kWideBvhLeaf | first << gpu::kWideBvhFirstShift | count;
        } else {
          uint32_t childNeed = 0;
          if (!collapse({s}, depth + 1, child, childNeed)) return false;
          deepest = std::max(deepest, childNeed);
        }
      }
      wide.loX[k] = lo.x, wide.loY[k] = lo.y, wide.loZ[k] = lo.z;
      wide.hiX[k] = hi.x, wide.hiY[k] = hi.y, wide.hiZ[k] = hi.z;
      wide.child[k] = child;
      wide.source[k] = source;
    }
    m_nodes[index] = wide;
    // At this node a traversal pushes every hit child but the nearest.
    need = uint32_t(slots.size()) - 1 + deepest;
    return true;
  }

  std::vector<gpu::GpuWideBvhNode> take() { return std::move(m_nodes); }

 private:
  const Bvh& m_bvh;
  std::vector<gpu::GpuWideBvhNode> m_nodes;
};

}  // namespace

std::vector<gpu::GpuWideBvhNode> collapseBvh(const Bvh& bvh) {
  // No triangles: the binary root's children are itself, under empty boxes (buildBvh).
  if (bvh.nodes.empty() || bvh.order.empty()) return {};
  const gpu::GpuBvhNode& root = bvh.nodes[0];
  std::vector<Slot> top;
  if (isLeaf(root)) {
    // No parent keeps the root's box: an unbounded one (every ray tests the leaf).
    top.push_back({glm::vec3(-FLT_MAX), glm::vec3(FLT_MAX), 0, gpu::kWideBvhEmpty});
  } else {
    top.push_back({glm::vec3(root.leftMinLeftIndex), glm::vec3(root.leftMaxRightIndex), word(root.leftMinLeftIndex.w), 0});
    top.push_back({glm::vec3(root.rightMinCount), glm::vec3(root.rightMaxFirst), word(root.leftMaxRightIndex.w), 1});
  }
  Collapser collapser(bvh);
  uint32_t index = 0, need = 0;
  if (!collapser.collapse(std::move(top), 0, index, need) || need > kBvhStackSize) return {};
  return collapser.take();
}

}  // namespace vktg
