#include "scene/primitives.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

namespace vktg {

TriangleMesh makeRectangle() {
  TriangleMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  // Counter-clockwise seen from +z: cross(+x, +y) = +z.
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh makeCube() {
  TriangleMesh mesh;
  // Vertex i has x, y, z = +1 where bit 0, 1, 2 of i is set, else -1.
  for (uint32_t i = 0; i < 8; ++i)
    mesh.positions.emplace_back((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f);
  // Each face as two triangles, counter-clockwise seen from outside.
  mesh.triangles = {
      {1, 3, 7}, {1, 7, 5},  // +x
      {0, 4, 6}, {0, 6, 2},  // -x
      {2, 6, 7}, {2, 7, 3},  // +y
      {0, 1, 5}, {0, 5, 4},  // -y
      {4, 5, 7}, {4, 7, 6},  // +z
      {0, 2, 3}, {0, 3, 1},  // -z
  };
  return mesh;
}

namespace {

// The 20 faces of the icosahedron are the vertex triples that are pairwise at the shortest
// distance; finding them avoids a hand-typed (and easily mis-wound) face table.
TriangleMesh makeIcosahedron() {
  const float phi = (1.0f + std::sqrt(5.0f)) * 0.5f;
  TriangleMesh mesh;
  for (float s : {-1.0f, 1.0f})
    for (float t : {-1.0f, 1.0f}) {
      mesh.positions.push_back(glm::normalize(glm::vec3(s, t * phi, 0)));
      mesh.positions.push_back(glm::normalize(glm::vec3(0, s, t * phi)));
      mesh.positions.push_back(glm::normalize(glm::vec3(t * phi, 0, s)));
    }
  const float edge = glm::distance(glm::normalize(glm::vec3(-1, -phi, 0)), glm::normalize(glm::vec3(1, -phi, 0)));
  auto adjacent = [&](uint32_t a, uint32_t b) {
    return std::abs(glm::distance(mesh.positions[a], mesh.positions[b]) - edge) < 1e-3f;
  };
  for (uint32_t a = 0; a < 12; ++a)
    for (uint32_t b = a + 1; b < 12; ++b)
      for (uint32_t c = b + 1; c < 12; ++c) {
        if (!adjacent(a, b) || !adjacent(b, c) || !adjacent(a, c)) continue;
        const glm::vec3 &p0 = mesh.positions[a], &p1 = mesh.positions[b], &p2 = mesh.positions[c];
        const bool outward = glm::dot(glm::cross(p1 - p0, p2 - p0), p0 + p1 + p2) > 0;
        mesh.triangles.push_back(outward ? glm::uvec3(a, b, c) : glm::uvec3(a, c, b));
      }
  return mesh;
}

}  // namespace

TriangleMesh makeIcosphere(uint32_t subdivisions) {
  TriangleMesh mesh = makeIcosahedron();
  for (uint32_t level = 0; level < subdivisions; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoints.try_emplace(key, uint32_t(mesh.positions.size()));
      if (inserted) mesh.positions.push_back(glm::normalize(mesh.positions[a] + mesh.positions[b]));
      return it->second;
    };
    std::vector<glm::uvec3> finer;
    finer.reserve(mesh.triangles.size() * 4);
    for (const glm::uvec3& t : mesh.triangles) {
      const uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
      // The four children keep the parent's orientation.
      finer.emplace_back(t.x, ab, ca);
      finer.emplace_back(ab, t.y, bc);
      finer.emplace_back(ca, bc, t.z);
      finer.emplace_back(ab, bc, ca);
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

TriangleMesh makeDisk(uint32_t segments) {
  TriangleMesh mesh;
  mesh.positions.reserve(size_t(segments) + 1);
  mesh.positions.emplace_back(0.0f, 0.0f, 0.0f);
  for (uint32_t k = 0; k < segments; ++k) {
    const double angle = 2.0 * std::numbers::pi * double(k) / double(segments);
    mesh.positions.emplace_back(float(std::cos(angle)), float(std::sin(angle)), 0.0f);
  }
  // Centre, rim k, rim k + 1 turn counter-clockwise seen from +z.
  for (uint32_t k = 0; k < segments; ++k) mesh.triangles.emplace_back(0u, 1u + k, 1u + (k + 1) % segments);
  return mesh;
}

TriangleMesh makeHeightfield(uint32_t nx, uint32_t nz, float sizeX, float sizeZ, const std::vector<float>& heights) {
  TriangleMesh mesh;
  mesh.positions.reserve(size_t(nx) * nz);
  for (uint32_t j = 0; j < nz; ++j)
    for (uint32_t i = 0; i < nx; ++i)
      mesh.positions.emplace_back(-0.5f * sizeX + sizeX * float(i) / float(nx - 1), heights[size_t(j) * nx + i],
                                  -0.5f * sizeZ + sizeZ * float(j) / float(nz - 1));
  auto index = [nx](uint32_t i, uint32_t j) { return j * nx + i; };
  for (uint32_t j = 0; j + 1 < nz; ++j)
    for (uint32_t i = 0; i + 1 < nx; ++i) {
      // (i, j) -> (i, j+1) -> (i+1, j) turns from +z to +x: cross(+z, +x) = +y, the front face.
      mesh.triangles.emplace_back(index(i, j), index(i, j + 1), index(i + 1, j));
      mesh.triangles.emplace_back(index(i + 1, j), index(i, j + 1), index(i + 1, j + 1));
    }
  return mesh;
}

glm::mat4 composeTransform(glm::vec3 translate, glm::vec3 rotateDegrees, glm::vec3 scale) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
  m = glm::rotate(m, glm::radians(rotateDegrees.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotateDegrees.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotateDegrees.x), glm::vec3(1, 0, 0));
  return glm::scale(m, scale);
}

void transformMesh(TriangleMesh& mesh, const glm::mat4& transform) {
  for (glm::vec3& p : mesh.positions) p = glm::vec3(transform * glm::vec4(p, 1.0f));
  if (glm::determinant(glm::mat3(transform)) < 0)
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

bool allFinite(const std::vector<glm::vec3>& positions) {
  return std::all_of(positions.begin(), positions.end(), [](const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  });
}

double meshArea(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles) {
  double area = 0;
  for (const glm::uvec3& t : triangles) {
    const glm::dvec3 p0(positions[t.x]), p1(positions[t.y]), p2(positions[t.z]);
    area += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
  }
  return area;
}

}  // namespace vktg
