// Binned-SAH BVH build in the GPU node layout and the CPU reference traversal.
//
// Triangle test: watertight (Woop, Benthin, Wald 2013). The ray is made the z axis of a sheared
// frame in which the three edge functions of a shared edge are exact negatives of each other, so
// a ray through an edge or a vertex never falls between two triangles. The shear is scaled by the
// direction's largest component instead of divided by it, so nothing before the hit distance
// divides: every decision is made from correctly rounded +, - and *, the same bits here and on
// any Vulkan device (the GLSL twin in shaders/lib/intersect.glsl is `precise`; this file is built
// without contraction).
//
// Why traversal equals brute force for every ray: the triangle test also requires t to lie inside
// the slab interval of the triangle's own padded box (trianglePaddedBox), computed with exactly the
// slab arithmetic the traversal applies to node boxes. Node boxes are unions of those padded
// boxes, and every step of the slab test (subtract, multiply by the same inverse direction,
// select, min/max, widen) is monotone under IEEE rounding, so a node's interval always contains
// the interval of every triangle below it: a node holding an accepted hit is never culled. Ties in
// t are broken by the smaller triangle index, which makes the closest hit independent of the
// visiting order.
//
// Hit distance: the test's t comes from coordinates relative to the ray origin, so its error
// grows with the triangle's distance from the origin (half a millimetre for a 1e4 m triangle). The
// reported t is therefore refined: the ray is re-intersected with the triangle's plane in
// double-float arithmetic (vktg/double_float.h), which leaves about one ulp of t
// (docs/precision.md states and measures the bound).
#include "vktg/bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include "vktg/double_float.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// Direction components smaller than this are replaced (keeping the sign) before inverting, so the
// inverse is finite and non-zero and the slab test never evaluates 0 * inf.
constexpr float kTinyDirection = 1e-30f;
// Relative widening of slab intervals in t: covers the rounding of the test's t relative to the
// slab t of the same point (errors proportional to the distance travelled).
constexpr float kSlabWiden = 1.0f / 8192.0f;
// Triangle boxes are padded by this fraction of their largest extent: covers errors of the test's
// t proportional to the triangle's size and distance.
constexpr float kPadRelative = 1.0f / 4096.0f;
// Rays closer to a triangle's plane than this (|d . n| relative to the product of the infinity
// norms of both edges and the direction, i.e. roughly the sine of the grazing angle) miss: below
// it the hit distance is rounding noise.
constexpr float kDetRelative = 1e-6f;

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  double area() const {
    glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
    if (e.x < 0 || e.y < 0 || e.z < 0) return 0.0;
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

Box trianglePaddedBox(const BvhTriangle& tri) {
  glm::vec3 lo = glm::min(glm::min(tri.p0, tri.p1), tri.p2);
  glm::vec3 hi = glm::max(glm::max(tri.p0, tri.p1), tri.p2);
  glm::vec3 ext = hi - lo;
  float pad = kPadRelative * std::max(std::max(ext.x, ext.y), ext.z);
  return {lo - pad, hi + pad};
}

struct PreparedRay {
  glm::vec3 origin, dir, invDir;
  int kx, ky, kz;  // kz: the direction's largest component (the first of equals); kx, ky follow it
};

PreparedRay prepareRay(glm::vec3 origin, glm::vec3 dir) {
  glm::vec3 inv;
  for (int i = 0; i < 3; ++i) {
    float d = dir[i];
    if (!(std::fabs(d) >= kTinyDirection)) d = std::signbit(d) ? -kTinyDirection : kTinyDirection;
    inv[i] = 1.0f / d;
  }
  glm::vec3 a = glm::abs(dir);
  int kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
  return {origin, dir, inv, (kz + 1) % 3, (kz + 2) % 3, kz};
}

float widenDown(float t) { return t * (t >= 0.0f ? 1.0f - kSlabWiden : 1.0f + kSlabWiden); }
float widenUp(float t) { return t * (t >= 0.0f ? 1.0f + kSlabWiden : 1.0f - kSlabWiden); }

// Widened [near, far] of the ray against a box; near > far when the ray misses it (inverted boxes
// included: the slab picks the face by the sign of the inverse, never by min/max of both).
glm::vec2 slabInterval(glm::vec3 lo, glm::vec3 hi, const PreparedRay& ray) {
  float tNear = -std::numeric_limits<float>::infinity();
  float tFar = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 3; ++i) {
    bool positive = ray.invDir[i] >= 0.0f;
    float nearFace = positive ? lo[i] : hi[i];
    float farFace = positive ? hi[i] : lo[i];
    tNear = std::max(tNear, (nearFace - ray.origin[i]) * ray.invDir[i]);
    tFar = std::min(tFar, (farFace - ray.origin[i]) * ray.invDir[i]);
  }
  return {widenDown(tNear), widenUp(tFar)};
}

float maxAbs(glm::vec3 v) { return std::max(std::max(std::fabs(v.x), std::fabs(v.y)), std::fabs(v.z)); }

std::optional<RayHit> intersectPrepared(const BvhTriangle& tri, const PreparedRay& ray, float tMin, float tMax) {
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const float dx = ray.dir[kx], dy = ray.dir[ky], dz = ray.dir[kz];
  const glm::vec3 a = tri.p0 - ray.origin, b = tri.p1 - ray.origin, c = tri.p2 - ray.origin;
  // Vertices in the sheared frame, scaled by dz: (dz x - dx z, dz y - dy z).
  auto shear = [&](glm::vec3 p) { return glm::vec2(dz * p[kx] - dx * p[kz], dz * p[ky] - dy * p[kz]); };
  const glm::vec2 as = shear(a), bs = shear(b), cs = shear(c);
  // Edge functions, each the (scaled) barycentric weight of the opposite vertex.
  const float w0 = cs.x * bs.y - cs.y * bs.x;
  const float w1 = as.x * cs.y - as.y * cs.x;
  const float w2 = bs.x * as.y - bs.y * as.x;
  if ((w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) && (w0 > 0.0f || w1 > 0.0f || w2 > 0.0f)) return std::nullopt;
  // det = dz (d . n): negated comparison so a NaN misses too.
  const float det = w0 + w1 + w2;
  const glm::vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  if (!(std::fabs(det) > kDetRelative * maxAbs(e1) * maxAbs(e2) * (dz * dz))) return std::nullopt;
  const float scaledT = w0 * a[kz] + w1 * b[kz] + w2 * c[kz];
  const float t = scaledT / (det * dz);
  if (!(t > tMin && t < tMax)) return std::nullopt;
  Box box = trianglePaddedBox(tri);
  glm::vec2 slab = slabInterval(box.lo, box.hi, ray);
  if (!(t >= slab.x && t <= slab.y)) return std::nullopt;
  RayHit hit;
  hit.t = t;
  hit.u = w1 / det;
  hit.v = w2 / det;
  return hit;
}

// The distance along the ray to the triangle's plane, (p0 - o) . n / (d . n) with n = e1 x e2, in
// double-float arithmetic: differences of floats are exact there and products lose about 2^-48,
// so the result is the float nearest the exact distance within about an ulp (docs/precision.md).
float refinedHitDistance(const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir, float t) {
  DoubleFloat e1[3], e2[3], a[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = twoSum(tri.p1[i], -tri.p0[i]);
    e2[i] = twoSum(tri.p2[i], -tri.p0[i]);
    a[i] = twoSum(tri.p0[i], -origin[i]);
  }
  DoubleFloat n[3];
  for (int i = 0; i < 3; ++i) {
    int j = (i + 1) % 3, k = (i + 2) % 3;
    n[i] = dfAdd(dfMul(e1[j], e2[k]), dfNegate(dfMul(e1[k], e2[j])));
  }
  DoubleFloat numerator, denominator;
  for (int i = 0; i < 3; ++i) {
    numerator = dfAdd(numerator, dfMul(a[i], n[i]));
    denominator = dfAdd(denominator, dfMul({dir[i], 0.0f}, n[i]));
  }
  // A plane the test accepted has d . n well away from 0; keep t if rounding says otherwise.
  if (!(std::fabs(denominator.hi) > 0.0f)) return t;
  float refined = dfDivide(numerator, denominator);
  return std::isfinite(refined) ? refined : t;
}

bool closer(const RayHit& a, const RayHit& b) { return a.t < b.t || (a.t == b.t && a.triangle < b.triangle); }

// ---- Build -------------------------------------------------------------------------------------

struct BuildItem {
  uint32_t node, begin, end, depth;
};

struct Split {
  bool found = false;
  int axis = 0;
  uint32_t bin = 0;  // left side = bins [0, bin)
  double cost = std::numeric_limits<double>::infinity();
  Box left, right;
};

uint32_t ceilLog2(uint32_t n) { return n <= 1 ? 0u : static_cast<uint32_t>(std::bit_width(n - 1)); }

class Builder {
 public:
  Builder(std::span<const BvhTriangle> triangles, const BvhBuildOptions& options)
      : m_options(options), m_boxes(triangles.size()), m_centroids(triangles.size()), m_index(triangles.size()) {
    for (size_t i = 0; i < triangles.size(); ++i) {
      m_boxes[i] = trianglePaddedBox(triangles[i]);
      m_centroids[i] = 0.5f * (m_boxes[i].lo + m_boxes[i].hi);
      m_index[i] = static_cast<uint32_t>(i);
    }
  }

  Bvh build() {
    Bvh bvh;
    uint32_t n = static_cast<uint32_t>(m_index.size());
    m_nodes.reserve(n > 0 ? 2 * n : 1);
    m_nodes.emplace_back();
    if (n == 0) {
      // An interior node whose children are empty boxes: every ray misses, the loop terminates.
      Box empty;
      setInterior(0, 0, empty, 0, empty, 0);
    } else {
      std::vector<BuildItem> stack{{0, 0, n, 0}};
      while (!stack.empty()) {
        BuildItem item = stack.back();
        stack.pop_back();
        process(item, stack);
      }
    }
    bvh.nodes = std::move(m_nodes);
    bvh.order = std::move(m_index);
    return bvh;
  }

 private:
  void setLeaf(uint32_t node, uint32_t first, uint32_t count) {
    gpu::GpuBvhNode& out = m_nodes[node];
    out.leftMinLeftIndex = glm::vec4(0.0f);
    out.leftMaxRightIndex = glm::vec4(0.0f);
    out.rightMinCount = glm::vec4(0.0f, 0.0f, 0.0f, std::bit_cast<float>(count));
    out.rightMaxFirst = glm::vec4(0.0f, 0.0f, 0.0f, std::bit_cast<float>(first));
  }

  // `rightFirst`: where the right subtree's triangles begin in leaf order.
  void setInterior(uint32_t node, uint32_t left, const Box& leftBox, uint32_t right, const Box& rightBox,
                   uint32_t rightFirst) {
    gpu::GpuBvhNode& out = m_nodes[node];
    out.leftMinLeftIndex = glm::vec4(leftBox.lo, std::bit_cast<float>(left));
    out.leftMaxRightIndex = glm::vec4(leftBox.hi, std::bit_cast<float>(right));
    out.rightMinCount = glm::vec4(rightBox.lo, std::bit_cast<float>(0u));
    out.rightMaxFirst = glm::vec4(rightBox.hi, std::bit_cast<float>(rightFirst));
  }

  void process(const BuildItem& item, std::vector<BuildItem>& stack) {
    uint32_t count = item.end - item.begin;
    Box centroidBounds;
    for (uint32_t i = item.begin; i < item.end; ++i) {
      glm::vec3 c = m_centroids[m_index[i]];
      centroidBounds.grow({c, c});
    }
    glm::vec3 extent = centroidBounds.hi - centroidBounds.lo;
    bool coincident = extent.x <= 0.0f && extent.y <= 0.0f && extent.z <= 0.0f;
    if (count == 1 || coincident) {
      setLeaf(item.node, item.begin, count);
      return;
    }

    Split split;
    // Invariant depth + ceil(log2(count)) <= maxDepth: a SAH split removes at least one triangle
    // per level, a median split halves the count, so once SAH would break the invariant median
    // splits take over and no leaf ends up deeper than maxDepth.
    bool sahAllowed = item.depth + ceilLog2(count) + 1 <= m_maxDepth;
    if (sahAllowed) {
      split = findSahSplit(item, centroidBounds);
      if (count <= m_options.maxLeafSize && (!split.found || static_cast<double>(count) <= split.cost)) {
        setLeaf(item.node, item.begin, count);
        return;
      }
    } else if (count <= m_options.maxLeafSize) {
      setLeaf(item.node, item.begin, count);
      return;
    }

    uint32_t mid;
    if (split.found) {
      mid = partitionByBin(item, centroidBounds, split);
    } else {
      mid = partitionByMedian(item, centroidBounds, split);
    }

    uint32_t left = static_cast<uint32_t>(m_nodes.size());
    m_nodes.emplace_back();
    m_nodes.emplace_back();
    setInterior(item.node, left, split.left, left + 1, split.right, mid);
    // Right pushed first so the left subtree is built (and laid out) first.
    stack.push_back({left + 1, mid, item.end, item.depth + 1});
    stack.push_back({left, item.begin, mid, item.depth + 1});
  }

  uint32_t binOf(glm::vec3 c, int axis, const Box& bounds, double scale) const {
    double x = (static_cast<double>(c[axis]) - static_cast<double>(bounds.lo[axis])) * scale;
    return std::min(m_bins - 1, static_cast<uint32_t>(x));
  }

  double binScale(const Box& bounds, int axis) const {
    return static_cast<double>(m_bins) /
           (static_cast<double>(bounds.hi[axis]) - static_cast<double>(bounds.lo[axis]));
  }

  Split findSahSplit(const BuildItem& item, const Box& centroidBounds) {
    struct Bin {
      Box box;
      uint32_t count = 0;
    };
    std::array<std::vector<Bin>, 3> bins;
    std::array<double, 3> scales{};
    std::array<bool, 3> active{};
    for (int axis = 0; axis < 3; ++axis) {
      active[axis] = centroidBounds.hi[axis] > centroidBounds.lo[axis];
      if (!active[axis]) continue;
      bins[axis].assign(m_bins, Bin{});
      scales[axis] = binScale(centroidBounds, axis);
    }
    for (uint32_t i = item.begin; i < item.end; ++i) {
      uint32_t tri = m_index[i];
      for (int axis = 0; axis < 3; ++axis) {
        if (!active[axis]) continue;
        Bin& bin = bins[axis][binOf(m_centroids[tri], axis, centroidBounds, scales[axis])];
        bin.box.grow(m_boxes[tri]);
        ++bin.count;
      }
    }

    Box parent;
    for (uint32_t i = item.begin; i < item.end; ++i) parent.grow(m_boxes[m_index[i]]);
    double parentArea = parent.area();

    Split best;
    std::vector<Box> rightBoxes(m_bins);
    std::vector<uint32_t> rightCounts(m_bins);
    for (int axis = 0; axis < 3; ++axis) {
      if (!active[axis]) continue;
      const std::vector<Bin>& b = bins[axis];
      Box acc;
      uint32_t accCount = 0;
      for (uint32_t k = m_bins - 1; k >= 1; --k) {
        acc.grow(b[k].box);
        accCount += b[k].count;
        rightBoxes[k] = acc;
        rightCounts[k] = accCount;
      }
      Box leftAcc;
      uint32_t leftCount = 0;
      for (uint32_t k = 1; k < m_bins; ++k) {
        leftAcc.grow(b[k - 1].box);
        leftCount += b[k - 1].count;
        if (leftCount == 0 || rightCounts[k] == 0) continue;
        // Flat scenes have zero-area parents: fall back to comparing unnormalised costs.
        double weighted = leftAcc.area() * leftCount + rightBoxes[k].area() * rightCounts[k];
        double cost = m_options.traversalCost + (parentArea > 0.0 ? weighted / parentArea : weighted);
        if (cost < best.cost) {
          best.found = true;
          best.cost = cost;
          best.axis = axis;
          best.bin = k;
          best.left = leftAcc;
          best.right = rightBoxes[k];
        }
      }
    }
    return best;
  }

  uint32_t partitionByBin(const BuildItem& item, const Box& centroidBounds, const Split& split) {
    double scale = binScale(centroidBounds, split.axis);
    auto first = m_index.begin() + item.begin;
    auto last = m_index.begin() + item.end;
    auto midIt = std::partition(first, last, [&](uint32_t tri) {
      return binOf(m_centroids[tri], split.axis, centroidBounds, scale) < split.bin;
    });
    return static_cast<uint32_t>(midIt - m_index.begin());
  }

  uint32_t partitionByMedian(const BuildItem& item, const Box& centroidBounds, Split& split) {
    glm::vec3 extent = centroidBounds.hi - centroidBounds.lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    uint32_t mid = item.begin + (item.end - item.begin) / 2;
    std::nth_element(m_index.begin() + item.begin, m_index.begin() + mid, m_index.begin() + item.end,
                     [&](uint32_t a, uint32_t b) {
                       float ca = m_centroids[a][axis], cb = m_centroids[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    split.left = Box{};
    split.right = Box{};
    for (uint32_t i = item.begin; i < mid; ++i) split.left.grow(m_boxes[m_index[i]]);
    for (uint32_t i = mid; i < item.end; ++i) split.right.grow(m_boxes[m_index[i]]);
    return mid;
  }

  BvhBuildOptions m_options;
  uint32_t m_bins = std::max(2u, m_options.bins);
  uint32_t m_maxDepth = m_options.maxDepth;
  std::vector<Box> m_boxes;
  std::vector<glm::vec3> m_centroids;
  std::vector<uint32_t> m_index;
  std::vector<gpu::GpuBvhNode> m_nodes;
};

uint32_t wordOf(float f) { return std::bit_cast<uint32_t>(f); }

template <bool kAnyHit>
std::optional<RayHit> traverse(const Bvh& bvh, std::span<const BvhTriangle> triangles, glm::vec3 origin,
                               glm::vec3 dir, float tMin, float tMax) {
  PreparedRay ray = prepareRay(origin, dir);
  std::optional<RayHit> best;
  float tBest = tMax;
  std::array<uint32_t, kBvhStackSize> stack;
  uint32_t size = 0;
  uint32_t node = 0;
  while (true) {
    const gpu::GpuBvhNode& n = bvh.nodes[node];
    uint32_t count = wordOf(n.rightMinCount.w);
    if (count > 0) {
      uint32_t first = wordOf(n.rightMaxFirst.w);
      for (uint32_t i = first; i < first + count; ++i) {
        std::optional<RayHit> hit = intersectPrepared(triangles[i], ray, tMin, tMax);
        if (!hit) continue;
        hit->triangle = i;
        if (kAnyHit) return hit;
        if (!best || closer(*hit, *best)) {
          best = hit;
          tBest = hit->t;
        }
      }
    } else {
      glm::vec2 l = slabInterval(glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex), ray);
      glm::vec2 r = slabInterval(glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst), ray);
      // Inclusive at tBest: a triangle at exactly tBest with a smaller index must still be found.
      bool hitLeft = std::max(l.x, tMin) <= std::min(l.y, tBest);
      bool hitRight = std::max(r.x, tMin) <= std::min(r.y, tBest);
      uint32_t leftNode = wordOf(n.leftMinLeftIndex.w);
      uint32_t rightNode = wordOf(n.leftMaxRightIndex.w);
      if (hitLeft && hitRight) {
        bool leftFirst = l.x <= r.x;
        stack[size++] = leftFirst ? rightNode : leftNode;
        node = leftFirst ? leftNode : rightNode;
        continue;
      }
      if (hitLeft || hitRight) {
        node = hitLeft ? leftNode : rightNode;
        continue;
      }
    }
    if (size == 0) break;
    node = stack[--size];
  }
  if (best) best->t = refinedHitDistance(triangles[best->triangle], origin, dir, best->t);
  return best;
}

}  // namespace

BvhRefitOrder bvhRefitOrder(const Bvh& bvh) {
  std::vector<std::vector<uint32_t>> levels;
  std::vector<std::pair<uint32_t, uint32_t>> frontier{{0u, 0u}};  // (node, depth)
  for (size_t i = 0; i < frontier.size(); ++i) {
    auto [node, depth] = frontier[i];
    const gpu::GpuBvhNode& n = bvh.nodes[node];
    if (wordOf(n.rightMinCount.w) > 0) continue;
    if (levels.size() <= depth) levels.resize(depth + 1);
    levels[depth].push_back(node);
    frontier.emplace_back(wordOf(n.leftMinLeftIndex.w), depth + 1);
    frontier.emplace_back(wordOf(n.leftMaxRightIndex.w), depth + 1);
  }
  BvhRefitOrder order;
  for (auto level = levels.rbegin(); level != levels.rend(); ++level) {
    order.levelStart.push_back(uint32_t(order.nodes.size()));
    order.nodes.insert(order.nodes.end(), level->begin(), level->end());
  }
  order.levelStart.push_back(uint32_t(order.nodes.size()));
  return order;
}

namespace {

Box nodeBox(const Bvh& bvh, std::span<const BvhTriangle> triangles, uint32_t node) {
  const gpu::GpuBvhNode& n = bvh.nodes[node];
  Box box;
  uint32_t count = wordOf(n.rightMinCount.w);
  if (count == 0) {
    box.grow({glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex)});
    box.grow({glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst)});
    return box;
  }
  uint32_t first = wordOf(n.rightMaxFirst.w);
  for (uint32_t i = first; i < first + count; ++i) box.grow(trianglePaddedBox(triangles[i]));
  return box;
}

}  // namespace

void refitBvh(Bvh& bvh, std::span<const BvhTriangle> triangles) {
  const BvhRefitOrder order = bvhRefitOrder(bvh);
  for (uint32_t node : order.nodes) {
    gpu::GpuBvhNode& n = bvh.nodes[node];
    Box left = nodeBox(bvh, triangles, wordOf(n.leftMinLeftIndex.w));
    Box right = nodeBox(bvh, triangles, wordOf(n.leftMaxRightIndex.w));
    n.leftMinLeftIndex = glm::vec4(left.lo, n.leftMinLeftIndex.w);
    n.leftMaxRightIndex = glm::vec4(left.hi, n.leftMaxRightIndex.w);
    n.rightMinCount = glm::vec4(right.lo, n.rightMinCount.w);
    n.rightMaxFirst = glm::vec4(right.hi, n.rightMaxFirst.w);
  }
}

namespace {

// The SAH cost of `bvh`'s topology with each inner node's children boxed by
// childBox(node, right): expected node visits (times `traversalCost`) plus triangle tests of a
// random ray through the root box.
template <class ChildBox>
double sahCostOf(const Bvh& bvh, float traversalCost, ChildBox childBox) {
  const gpu::GpuBvhNode& root = bvh.nodes.at(0);
  if (wordOf(root.rightMinCount.w) > 0) return double(wordOf(root.rightMinCount.w));
  Box rootBox;
  rootBox.grow(childBox(root, false));
  rootBox.grow(childBox(root, true));
  const double rootArea = std::max(rootBox.area(), 1e-300);
  double cost = traversalCost;  // the root is always visited
  for (const gpu::GpuBvhNode& n : bvh.nodes) {
    if (wordOf(n.rightMinCount.w) > 0) continue;
    for (bool right : {false, true}) {
      const uint32_t child = wordOf(right ? n.leftMaxRightIndex.w : n.leftMinLeftIndex.w);
      const uint32_t count = wordOf(bvh.nodes[child].rightMinCount.w);
      cost += childBox(n, right).area() / rootArea * (count > 0 ? double(count) : double(traversalCost));
    }
  }
  return cost;
}

}  // namespace

double bvhSahCost(const Bvh& bvh, float traversalCost) {
  return sahCostOf(bvh, traversalCost, [](const gpu::GpuBvhNode& n, bool right) {
    return right ? Box{glm::vec3(n.rightMinCount), glm::vec3(n.rightMaxFirst)}
                 : Box{glm::vec3(n.leftMinLeftIndex), glm::vec3(n.leftMaxRightIndex)};
  });
}

double refitSahCost(const Bvh& bvh, std::span<const BvhTriangle> triangles, float traversalCost) {
  if (triangles.empty()) return bvhSahCost(bvh, traversalCost);  // an empty tree's root is its own child
  // Every node's box after a refit (refitBvh's nodeBox, by the same min and max), children first:
  // the builder appends a node's children after it, so reverse index order visits them before it.
  std::vector<Box> boxes(bvh.nodes.size());
  for (size_t i = bvh.nodes.size(); i-- > 0;) {
    const gpu::GpuBvhNode& n = bvh.nodes[i];
    const uint32_t count = wordOf(n.rightMinCount.w);
    if (count > 0) {
      if (size_t(wordOf(n.rightMaxFirst.w)) + count > triangles.size())
        throw Error("internal: a BVH leaf beyond the triangles refit to");
      boxes[i] = nodeBox(bvh, triangles, uint32_t(i));
      continue;
    }
    const uint32_t left = wordOf(n.leftMinLeftIndex.w), right = wordOf(n.leftMaxRightIndex.w);
    if (left <= i || right <= i || left >= boxes.size() || right >= boxes.size())
      throw Error("internal: a BVH node's children precede it");
    boxes[i].grow(boxes[left]);
    boxes[i].grow(boxes[right]);
  }
  return sahCostOf(bvh, traversalCost, [&](const gpu::GpuBvhNode& n, bool right) {
    return boxes[wordOf(right ? n.leftMaxRightIndex.w : n.leftMinLeftIndex.w)];
  });
}

Bvh buildBvh(std::span<const BvhTriangle> triangles, const BvhBuildOptions& options) {
  if (options.maxLeafSize == 0) fail("", "bvh.maxLeafSize", "must be at least 1");
  if (options.bins < 2) fail("", "bvh.bins", "must be at least 2");
  if (options.maxDepth < 1 || options.maxDepth > kBvhStackSize)
    fail("", "bvh.maxDepth", "must be in [1, " + std::to_string(kBvhStackSize) + "]");
  if (triangles.size() >= (size_t{1} << 31)) fail("", "bvh", "too many triangles");
  if (ceilLog2(static_cast<uint32_t>(triangles.size())) > options.maxDepth)
    fail("", "bvh.maxDepth", "too small for " + std::to_string(triangles.size()) + " triangles");
  return Builder(triangles, options).build();
}

std::optional<RayHit> intersectTriangle(const BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir, float tMin,
                                        float tMax) {
  std::optional<RayHit> hit = intersectPrepared(tri, prepareRay(origin, dir), tMin, tMax);
  if (hit) hit->t = refinedHitDistance(tri, origin, dir, hit->t);
  return hit;
}

std::optional<RayHit> traceClosest(const Bvh& bvh, std::span<const BvhTriangle> triangles, glm::vec3 origin,
                                   glm::vec3 dir, float tMin, float tMax) {
  return traverse<false>(bvh, triangles, origin, dir, tMin, tMax);
}

bool traceAny(const Bvh& bvh, std::span<const BvhTriangle> triangles, glm::vec3 origin, glm::vec3 dir,
              float tMin, float tMax) {
  return traverse<true>(bvh, triangles, origin, dir, tMin, tMax).has_value();
}

void forEachTriangleNearBox(const Bvh& bvh, glm::vec3 lo, glm::vec3 hi, const std::function<void(uint32_t)>& visit) {
  if (bvh.nodes.empty()) return;
  auto meets = [&](glm::vec4 boxLo, glm::vec4 boxHi) {
    return glm::all(glm::lessThanEqual(glm::vec3(boxLo), hi)) && glm::all(glm::lessThanEqual(lo, glm::vec3(boxHi)));
  };
  std::array<uint32_t, kBvhStackSize> stack;
  uint32_t size = 0, node = 0;
  while (true) {
    const gpu::GpuBvhNode& n = bvh.nodes[node];
    if (uint32_t count = wordOf(n.rightMinCount.w); count > 0) {
      for (uint32_t i = wordOf(n.rightMaxFirst.w), end = i + count; i < end; ++i) visit(i);
    } else {
      bool left = meets(n.leftMinLeftIndex, n.leftMaxRightIndex), right = meets(n.rightMinCount, n.rightMaxFirst);
      if (left && right) stack[size++] = wordOf(n.leftMaxRightIndex.w);
      if (left || right) {
        node = wordOf(left ? n.leftMinLeftIndex.w : n.leftMaxRightIndex.w);
        continue;
      }
    }
    if (size == 0) break;
    node = stack[--size];
  }
}

std::optional<RayHit> traceClosestBruteForce(std::span<const BvhTriangle> triangles, glm::vec3 origin,
                                             glm::vec3 dir, float tMin, float tMax) {
  PreparedRay ray = prepareRay(origin, dir);
  std::optional<RayHit> best;
  for (size_t i = 0; i < triangles.size(); ++i) {
    std::optional<RayHit> hit = intersectPrepared(triangles[i], ray, tMin, tMax);
    if (!hit) continue;
    hit->triangle = static_cast<uint32_t>(i);
    if (!best || closer(*hit, *best)) best = hit;
  }
  if (best) best->t = refinedHitDistance(triangles[best->triangle], origin, dir, best->t);
  return best;
}

}  // namespace vktg
