#include "vktg/silhouette_edges.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "scene/selection_cdf.h"

namespace vktg {
namespace {

// An end of an edge identified by its exact position (bit pattern).
using PositionKey = std::array<uint32_t, 3>;

PositionKey keyOf(const glm::vec3& p) {
  PositionKey k;
  std::memcpy(k.data(), &p, sizeof k);
  return k;
}

// Per vertex, the rank of its position among the scene's distinct positions in PositionKey order:
// vertices at the same position (a seam) share it, and comparing ranks compares the positions.
std::vector<uint32_t> positionRanks(const PreparedScene& prepared) {
  const size_t count = prepared.vertices.size();
  std::vector<PositionKey> keys(count);
  for (size_t v = 0; v < count; ++v) keys[v] = keyOf(glm::vec3(prepared.vertices[v]));
  std::vector<uint32_t> order(count);
  for (uint32_t v = 0; v < count; ++v) order[v] = v;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  std::vector<uint32_t> rank(count);
  uint32_t distinct = 0;
  for (size_t i = 0; i < count; ++i) {
    if (i > 0 && keys[order[i]] != keys[order[i - 1]]) ++distinct;
    rank[order[i]] = distinct;
  }
  return rank;
}

// One face's side of an edge: the rank of the edge's higher end and where the side was met, the
// triangle's index times 3 plus the edge's place in it.
struct EdgeSide {
  uint32_t upper;
  uint64_t visit;
};

// What an edge's first two faces say about it (further faces only count).
struct EdgeFaces {
  uint32_t count = 0;
  uint32_t vertex0 = 0, vertex1 = 0;  // global vertex indices of the ends (first face seen)
  // Per face: the unit in-face direction perpendicular to the edge, and the unit normal.
  glm::vec3 inward[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
  glm::vec3 normal[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
  uint32_t opposite[2] = {0, 0};      // per face: the vertex not on the edge
  uint32_t triangle[2] = {0, 0};      // per face: its triangle (the prepared scene's leaf order)
};

// Faces closer to coplanar than this (1 - cos of the dihedral deviation) form a flat crease.
constexpr float kFlatCrease = 1e-6f;

// Calls visit(faces) for the edges of every non-degenerate triangle in order of their ends'
// positions (lower end first, then higher), each edge's faces in the order the triangles list them.
// A bucket sort by the lower end's rank, then by the higher end's within a bucket (a vertex's few
// edges): at 2M triangles a map with a node and vectors per edge took seconds.
template <class Visit>
void forEachEdge(const PreparedScene& prepared, Visit visit) {
  const std::vector<uint32_t> rank = positionRanks(prepared);
  struct Corners {
    uint32_t ids[3];
    glm::vec3 p[3];
    glm::vec3 n;
  };
  auto corners = [&](size_t triangle, Corners& c) {
    const glm::uvec4& tri = prepared.triangleVerts[triangle];
    c.ids[0] = tri.x, c.ids[1] = tri.y, c.ids[2] = tri.z;
    for (int i = 0; i < 3; ++i) c.p[i] = glm::vec3(prepared.vertices[c.ids[i]]);
    c.n = glm::cross(c.p[1] - c.p[0], c.p[2] - c.p[0]);
    if (!(glm::length(c.n) > 0.0f)) return false;  // degenerate triangles bound nothing
    c.n = glm::normalize(c.n);
    return true;
  };
  // Every side's bucket (its lower end's rank) and EdgeSide, in the order the triangles list them:
  // walked twice, to count the buckets and then to fill them, rather than held in a third array.
  Corners c;
  auto forEachSide = [&](auto&& use) {
    for (size_t t = 0; t < prepared.triangleVerts.size(); ++t) {
      if (!corners(t, c)) continue;
      for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        if (!(glm::length(c.p[j] - c.p[i]) > 0.0f)) continue;
        uint32_t a = rank[c.ids[i]], b = rank[c.ids[j]];
        use(std::min(a, b), EdgeSide{std::max(a, b), 3 * uint64_t(t) + uint64_t(i)});
      }
    }
  };
  std::vector<size_t> start(rank.size() + 1, 0);
  forEachSide([&](uint32_t bucket, const EdgeSide&) { ++start[bucket + 1]; });
  for (size_t r = 0; r < rank.size(); ++r) start[r + 1] += start[r];
  std::vector<EdgeSide> sides(start.back());
  {
    std::vector<size_t> next(start.begin(), start.end() - 1);
    forEachSide([&](uint32_t bucket, const EdgeSide& side) { sides[next[bucket]++] = side; });
  }
  for (size_t r = 0; r < rank.size(); ++r) {
    // Stable: sides of one edge stay in the order they were listed. A vertex has a few edges, whose
    // insertion sort needs no buffer; a fan's centre (a disc's) may have thousands.
    auto first = sides.begin() + start[r], last = sides.begin() + start[r + 1];
    if (last - first > 32) {
      std::stable_sort(first, last, [](const EdgeSide& x, const EdgeSide& y) { return x.upper < y.upper; });
    } else {
      for (auto i = first; i != last; ++i)
        for (auto j = i; j != first && (j - 1)->upper > j->upper; --j) std::iter_swap(j - 1, j);
    }
    for (size_t s = start[r]; s < start[r + 1];) {
      EdgeFaces faces;
      size_t end = s;
      while (end < start[r + 1] && sides[end].upper == sides[s].upper) ++end;
      faces.count = uint32_t(end - s);
      for (uint32_t face = 0; face < 2 && face < faces.count; ++face) {
        const EdgeSide& side = sides[s + face];
        corners(side.visit / 3, c);
        int i = int(side.visit % 3), j = (i + 1) % 3, k = (i + 2) % 3;
        if (face == 0) {
          bool swapped = keyOf(c.p[j]) < keyOf(c.p[i]);
          faces.vertex0 = swapped ? c.ids[j] : c.ids[i];
          faces.vertex1 = swapped ? c.ids[i] : c.ids[j];
        }
        glm::vec3 inward = glm::cross(c.n, c.p[j] - c.p[i]);
        if (glm::dot(inward, c.p[k] - c.p[i]) < 0.0f) inward = -inward;
        faces.inward[face] = glm::normalize(inward);
        faces.normal[face] = c.n;
        faces.opposite[face] = c.ids[k];
        faces.triangle[face] = uint32_t(side.visit / 3);
      }
      visit(faces);
      s = end;
    }
  }
}

}  // namespace

std::vector<gpu::GpuEdge> silhouetteEdges(const PreparedScene& prepared, const std::vector<bool>& movingVertex) {
  return edgeList(prepared, movingVertex, {}).edges;
}

EdgeList edgeList(const PreparedScene& prepared, const std::vector<bool>& movingVertex,
                  const std::vector<bool>& deformingVertex) {
  EdgeList list;
  std::vector<gpu::GpuEdge>& out = list.edges;
  std::vector<double> lengths;
  std::vector<bool> moving;
  double total = 0, totalMoving = 0;
  auto moves = [&](uint32_t v) { return !movingVertex.empty() && movingVertex.at(v); };
  auto deforms = [&](uint32_t v) { return !deformingVertex.empty() && deformingVertex.at(v); };
  forEachEdge(prepared, [&](const EdgeFaces& faces) {
    bool flat = faces.count >= 2 && std::abs(glm::dot(faces.normal[0], faces.normal[1])) > 1.0f - kFlatCrease &&
                glm::dot(faces.inward[0], faces.inward[1]) < 0.0f;
    // A flat crease: the two faces continue each other, unless motion folds them.
    if (flat && !(deforms(faces.vertex0) || deforms(faces.vertex1) || deforms(faces.opposite[0]) ||
                  deforms(faces.opposite[1])))
      return;
    gpu::GpuEdge edge{};
    glm::vec3 p0 = glm::vec3(prepared.vertices[faces.vertex0]), p1 = glm::vec3(prepared.vertices[faces.vertex1]);
    uint32_t v0 = faces.vertex0, v1 = faces.vertex1;
    edge.p0 = glm::vec4(p0, 0.0f);
    edge.p1 = glm::vec4(p1, 0.0f);
    std::memcpy(&edge.p0.w, &v0, sizeof v0);
    std::memcpy(&edge.p1.w, &v1, sizeof v1);
    edge.inward0 = glm::vec4(faces.inward[0], 0.0f);
    edge.inward1 = glm::vec4(faces.count >= 2 ? faces.inward[1] : glm::vec3(0.0f), 0.0f);
    out.push_back(edge);
    const bool twoFaces = faces.count >= 2;
    list.faces.emplace_back(faces.opposite[0], twoFaces ? faces.opposite[1] : 0xffffffffu, faces.triangle[0],
                            twoFaces ? faces.triangle[1] : 0xffffffffu);
    lengths.push_back(glm::length(p1 - p0));
    moving.push_back(moves(v0) || moves(v1));
    total += lengths.back();
    if (moving.back()) totalMoving += lengths.back();
  });
  // Mixing only when it changes something: some edges move and some do not.
  const double movingShare = totalMoving > 0 && totalMoving < total ? kMovingEdgeShare : 0.0;
  // In 32-bit fixed point (selection_cdf.h): sample_edges compares 32-bit numbers against the ends,
  // so each edge is picked with exactly the pmf its weight divides by, among millions of edges too.
  std::vector<double> weights(out.size());
  for (size_t i = 0; i < out.size(); ++i)
    weights[i] = (1.0 - movingShare) * lengths[i] / total + (moving[i] ? movingShare * lengths[i] / totalMoving : 0.0);
  const uint64_t scale = uint64_t(1) << 32;
  const std::vector<uint64_t> ends = selectionIntervalEnds(weights, scale);
  uint64_t start = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const uint32_t stored = uint32_t(ends[i]);  // the last edge's 2^32 wraps to 0
    std::memcpy(&out[i].inward0.w, &stored, sizeof stored);
    out[i].inward1.w = float(double(ends[i] - start) / double(scale));
    start = ends[i];
  }
  return list;
}

}  // namespace vktg
