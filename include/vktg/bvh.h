// Binned-SAH BVH built on the host in the GPU node layout (gpu::GpuBvhNode), plus the CPU
// traversal the tests use as the reference for shaders/lib/bvh.glsl.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/gpu/shared.h"

namespace vktg {

struct BvhTriangle {
  glm::vec3 p0, p1, p2;
};

struct Bvh {
  std::vector<gpu::GpuBvhNode> nodes;  // nodes[0] is the root
  std::vector<uint32_t> order;         // leaf order: order[i] = input index of the i-th triangle
};

// Entries of the traversal stack (here and in shaders/lib/bvh.glsl): the builder keeps every leaf at
// depth <= maxDepth <= kBvhStackSize (root = depth 0), and near-first traversal never holds more
// entries than the depth of the node it is at.
inline constexpr uint32_t kBvhStackSize = 64;

struct BvhBuildOptions {
  uint32_t bins = 16;            // SAH bins per axis
  uint32_t maxLeafSize = 4;      // leaves never exceed this many triangles unless they cannot split
  float traversalCost = 1.0f;    // SAH cost of a node visit relative to a triangle test
  uint32_t maxDepth = kBvhStackSize;  // deepest leaf; near the limit SAH gives way to median splits
};

Bvh buildBvh(std::span<const BvhTriangle> triangles, const BvhBuildOptions& options = {});

// The tree collapsed to 4 children per node (gpu::GpuWideBvhNode), for the traversal of CPU devices
// (kSpecWideBvh): each node adopts the children of its largest-area inner children until it has 4.
// Triangle order, boxes and leaves are the binary tree's, so a traversal finds the same hits.
// Empty where the layout cannot hold the tree: a leaf of more than kWideBvhMaxLeafCount triangles,
// a first triangle past kWideBvhMaxFirst, or a near-first traversal that could need more than
// kBvhStackSize stack entries.
std::vector<gpu::GpuWideBvhNode> collapseBvh(const Bvh& bvh);

// Internal nodes by depth, deepest level first: a bottom-up refit can process
// nodes[levelStart[l] .. levelStart[l + 1]) in parallel once the levels before it are done.
struct BvhRefitOrder {
  std::vector<uint32_t> nodes;
  std::vector<uint32_t> levelStart;  // levels + 1 entries
};
BvhRefitOrder bvhRefitOrder(const Bvh& bvh);

// Recomputes every internal node's child boxes for moved triangles (`triangles` in leaf order), as
// shaders/refit_bvh.comp does: the topology stays, the traversal stays exact.
void refitBvh(Bvh& bvh, std::span<const BvhTriangle> triangles);

// Surface-area-heuristic cost of the tree: expected node visits (times `traversalCost`) plus
// triangle tests of a random ray through the root box. A refit tree's cost over the cost it had
// when built measures how far motion has degraded it.
double bvhSahCost(const Bvh& bvh, float traversalCost = 1.0f);

// bvhSahCost of the tree refit to `triangles` (leaf order), bit for bit, without changing or
// copying it: one pass over the nodes for their boxes, one for the sum. The host twin of what an
// optimisation's check of its moving scene's tree sums on the device (shaders/bvh_sah_cost.comp,
// after refit_bvh), which tests hold to it.
double refitSahCost(const Bvh& bvh, std::span<const BvhTriangle> triangles, float traversalCost = 1.0f);

struct RayHit {
  float t = 0;
  float u = 0, v = 0;       // barycentrics: p = (1-u-v) p0 + u p1 + v p2
  uint32_t triangle = 0;    // index in leaf order (as on the GPU)
};

// Watertight ray-triangle test as in shaders/lib/intersect.glsl; both faces hit. Hit distances
// (here and from the traversals) are refined against the triangle's plane: within about one ulp of
// the exact distance (docs/precision.md); the window (tMin, tMax) is applied before refinement.
std::optional<RayHit> intersectTriangle(const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir,
                                        float tMin, float tMax);
// `triangles` in leaf order (triangles[i] = input[order[i]]).
std::optional<RayHit> traceClosest(const Bvh& bvh, std::span<const BvhTriangle> triangles,
                                   glm::vec3 origin, glm::vec3 dir, float tMin, float tMax);
bool traceAny(const Bvh& bvh, std::span<const BvhTriangle> triangles, glm::vec3 origin, glm::vec3 dir,
              float tMin, float tMax);
// Calls visit(i) for every triangle (leaf order) in a leaf whose box the query box [lo, hi] meets:
// a superset of the triangles that meet it, each once.
void forEachTriangleNearBox(const Bvh& bvh, glm::vec3 lo, glm::vec3 hi, const std::function<void(uint32_t)>& visit);
// Brute force over all triangles (tests' ground truth).
std::optional<RayHit> traceClosestBruteForce(std::span<const BvhTriangle> triangles, glm::vec3 origin,
                                             glm::vec3 dir, float tMin, float tMax);

}  // namespace vktg
