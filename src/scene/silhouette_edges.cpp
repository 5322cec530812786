#include "vktg/silhouette_edges.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <map>

#include <glm/glm.hpp>

namespace vktg {
namespace {

// An end of an edge identified by its exact position (bit pattern).
using PositionKey = std::array<uint32_t, 3>;

PositionKey keyOf(const glm::vec3& p) {
  PositionKey k;
  std::memcpy(k.data(), &p, sizeof k);
  return k;
}

struct EdgeFaces {
  uint32_t vertex0 = 0, vertex1 = 0;  // global vertex indices of the ends (first face seen)
  std::vector<glm::vec3> inward;      // per face: unit in-face direction perpendicular to the edge
  std::vector<glm::vec3> normal;      // per face: unit normal
  std::vector<uint32_t> opposite;     // per face: the vertex not on the edge
};

// Faces closer to coplanar than this (1 - cos of the dihedral deviation) form a flat crease.
constexpr float kFlatCrease = 1e-6f;

}  // namespace

std::vector<gpu::GpuEdge> silhouetteEdges(const PreparedScene& prepared, const std::vector<bool>& movingVertex) {
  return edgeList(prepared, movingVertex, {}).edges;
}

EdgeList edgeList(const PreparedScene& prepared, const std::vector<bool>& movingVertex,
                  const std::vector<bool>& deformingVertex) {
  std::map<std::pair<PositionKey, PositionKey>, EdgeFaces> edges;
  for (const glm::uvec4& tri : prepared.triangleVerts) {
    uint32_t ids[3] = {tri.x, tri.y, tri.z};
    glm::vec3 p[3];
    for (int i = 0; i < 3; ++i) p[i] = glm::vec3(prepared.vertices[ids[i]]);
    glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    if (!(glm::length(n) > 0.0f)) continue;  // degenerate triangles bound nothing
    n = glm::normalize(n);
    for (int i = 0; i < 3; ++i) {
      int j = (i + 1) % 3, k = (i + 2) % 3;
      glm::vec3 e = p[j] - p[i];
      if (!(glm::length(e) > 0.0f)) continue;
      PositionKey a = keyOf(p[i]), b = keyOf(p[j]);
      bool swapped = b < a;
      EdgeFaces& faces = edges[swapped ? std::make_pair(b, a) : std::make_pair(a, b)];
      if (faces.inward.empty()) {
        faces.vertex0 = swapped ? ids[j] : ids[i];
        faces.vertex1 = swapped ? ids[i] : ids[j];
      }
      glm::vec3 inward = glm::cross(n, e);
      if (glm::dot(inward, p[k] - p[i]) < 0.0f) inward = -inward;
      faces.inward.push_back(glm::normalize(inward));
      faces.normal.push_back(n);
      faces.opposite.push_back(ids[k]);
    }
  }
  EdgeList list;
  std::vector<gpu::GpuEdge>& out = list.edges;
  std::vector<double> lengths;
  std::vector<bool> moving;
  double total = 0, totalMoving = 0;
  auto moves = [&](uint32_t v) { return !movingVertex.empty() && movingVertex.at(v); };
  auto deforms = [&](uint32_t v) { return !deformingVertex.empty() && deformingVertex.at(v); };
  for (const auto& [key, faces] : edges) {
    bool flat = faces.inward.size() >= 2 && std::abs(glm::dot(faces.normal[0], faces.normal[1])) > 1.0f - kFlatCrease &&
                glm::dot(faces.inward[0], faces.inward[1]) < 0.0f;
    // A flat crease: the two faces continue each other, unless motion folds them.
    if (flat && !(deforms(faces.vertex0) || deforms(faces.vertex1) || deforms(faces.opposite[0]) ||
                  deforms(faces.opposite[1])))
      continue;
    gpu::GpuEdge edge{};
    glm::vec3 p0 = glm::vec3(prepared.vertices[faces.vertex0]), p1 = glm::vec3(prepared.vertices[faces.vertex1]);
    uint32_t v0 = faces.vertex0, v1 = faces.vertex1;
    edge.p0 = glm::vec4(p0, 0.0f);
    edge.p1 = glm::vec4(p1, 0.0f);
    std::memcpy(&edge.p0.w, &v0, sizeof v0);
    std::memcpy(&edge.p1.w, &v1, sizeof v1);
    edge.inward0 = glm::vec4(faces.inward[0], 0.0f);
    edge.inward1 = glm::vec4(faces.inward.size() >= 2 ? faces.inward[1] : glm::vec3(0.0f), 0.0f);
    out.push_back(edge);
    list.faces.emplace_back(faces.opposite[0], faces.opposite.size() >= 2 ? faces.opposite[1] : 0xffffffffu, 0u, 0u);
    lengths.push_back(glm::length(p1 - p0));
    moving.push_back(moves(v0) || moves(v1));
    total += lengths.back();
    if (moving.back()) totalMoving += lengths.back();
  }
  // Mixing only when it changes something: some edges move and some do not.
  const double movingShare = totalMoving > 0 && totalMoving < total ? kMovingEdgeShare : 0.0;
  double cdf = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    double pmf = (1.0 - movingShare) * lengths[i] / total + (moving[i] ? movingShare * lengths[i] / totalMoving : 0.0);
    cdf += pmf;
    out[i].inward0.w = float(cdf);
    out[i].inward1.w = float(pmf);
  }
  if (!out.empty()) out.back().inward0.w = 1.0f;
  return list;
}

}  // namespace vktg
