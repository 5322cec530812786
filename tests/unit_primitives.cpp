// Built-in shapes: counts, areas, the documented front faces, closedness, and transforms.
#include <cmath>
#include <map>
#include <utility>

#include <gtest/gtest.h>

#include "scene/primitives.h"

namespace vktg {
namespace {

glm::dvec3 normalOf(const TriangleMesh& mesh, const glm::uvec3& t) {
  const glm::dvec3 p0(mesh.positions[t.x]), p1(mesh.positions[t.y]), p2(mesh.positions[t.z]);
  return glm::normalize(glm::cross(p1 - p0, p2 - p0));
}

glm::dvec3 centroidOf(const TriangleMesh& mesh, const glm::uvec3& t) {
  return (glm::dvec3(mesh.positions[t.x]) + glm::dvec3(mesh.positions[t.y]) + glm::dvec3(mesh.positions[t.z])) / 3.0;
}

// A closed, consistently wound surface uses every directed edge exactly once and its reverse
// exactly once; a flipped triangle would use some directed edge twice.
void expectClosedAndConsistent(const TriangleMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : mesh.triangles) {
    ++directed[{t.x, t.y}];
    ++directed[{t.y, t.z}];
    ++directed[{t.z, t.x}];
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "edge " << edge.first << "-" << edge.second << " is open";
  }
  // Euler characteristic of a sphere: V - E + F = 2.
  EXPECT_EQ(int64_t(mesh.positions.size()) - int64_t(directed.size() / 2) + int64_t(mesh.triangles.size()), 2);
}

TEST(Primitives, RectangleIsTheSquareFacingPlusZ) {
  const TriangleMesh mesh = makeRectangle();
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_DOUBLE_EQ(meshArea(mesh.positions, mesh.triangles), 4.0);
  for (const glm::vec3& p : mesh.positions) {
    EXPECT_EQ(std::abs(p.x), 1.0f);
    EXPECT_EQ(std::abs(p.y), 1.0f);
    EXPECT_EQ(p.z, 0.0f);
  }
  for (const glm::uvec3& t : mesh.triangles) EXPECT_NEAR(normalOf(mesh, t).z, 1.0, 1e-12);
}

TEST(Primitives, CubeFacesPointOutward) {
  const TriangleMesh mesh = makeCube();
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.positions.size(), 8u);
  EXPECT_DOUBLE_EQ(meshArea(mesh.positions, mesh.triangles), 24.0);
  std::map<std::pair<int, int>, int> perFace;  // (axis, sign) -> triangles
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 n = normalOf(mesh, t), c = centroidOf(mesh, t);
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
    EXPECT_NEAR(std::abs(n[axis]), 1.0, 1e-12);
    // The centroid of a face triangle lies on the face, at +-1 along the normal's axis.
    EXPECT_NEAR(c[axis], n[axis], 1e-12) << "triangle faces inward";
    ++perFace[{axis, n[axis] > 0 ? 1 : -1}];
  }
  EXPECT_EQ(perFace.size(), 6u);
  for (const auto& [face, count] : perFace) EXPECT_EQ(count, 2);
  expectClosedAndConsistent(mesh);
}

TEST(Primitives, IcosphereCountsAndOrientation) {
  for (uint32_t s = 0; s <= 4; ++s) {
    const TriangleMesh mesh = makeIcosphere(s);
    const size_t faces = 20u << (2 * s);
    EXPECT_EQ(mesh.triangles.size(), faces);
    EXPECT_EQ(mesh.positions.size(), faces / 2 + 2);  // from V - E + F = 2 and E = 3F/2
    for (const glm::vec3& p : mesh.positions) EXPECT_NEAR(glm::length(p), 1.0f, 1e-6f);
    for (const glm::uvec3& t : mesh.triangles) EXPECT_GT(glm::dot(normalOf(mesh, t), centroidOf(mesh, t)), 0.0);
    expectClosedAndConsistent(mesh);
  }
}

// Radially projecting each flat triangle onto the unit sphere covers the sphere exactly once; the
// projection's area scale at a point at radius r on a plane at distance d is d / r^3, with
// d <= r <= 1, so 4 pi d_min^2 <= area <= 4 pi, where d_min is the smallest distance from the
// centre to a triangle's plane. The bound is computed from the mesh, and d_min -> 1 as s grows.
TEST(Primitives, IcosphereAreaApproachesFourPiWithinDerivedBound) {
  double previous = 0;
  for (uint32_t s = 0; s <= 6; ++s) {
    const TriangleMesh mesh = makeIcosphere(s);
    double dMin = 1;
    for (const glm::uvec3& t : mesh.triangles)
      dMin = std::min(dMin, std::abs(glm::dot(normalOf(mesh, t), glm::dvec3(mesh.positions[t.x]))));
    const double area = meshArea(mesh.positions, mesh.triangles);
    const double tolerance = 1e-9 * 4 * M_PI;  // float vertex positions summed in double
    EXPECT_LE(area, 4 * M_PI + tolerance) << "s = " << s;
    EXPECT_GE(area, 4 * M_PI * dMin * dMin - tolerance) << "s = " << s;
    EXPECT_GT(area, previous) << "refining must add area, s = " << s;
    previous = area;
    if (s == 6) {
      EXPECT_GT(dMin, 0.9998);  // edge length ~ 1.1 / 2^6, so 1 - d ~ edge^2 / 6
      EXPECT_NEAR(area, 4 * M_PI, 4 * M_PI * (1 - dMin * dMin));
    }
  }
}

TEST(Primitives, DiskIsAFanInscribedInTheUnitCircleFacingPlusZ) {
  for (uint32_t segments : {3u, 4u, 64u}) {
    const TriangleMesh mesh = makeDisk(segments);
    ASSERT_EQ(mesh.triangles.size(), segments);
    ASSERT_EQ(mesh.positions.size(), segments + 1u);
    EXPECT_EQ(mesh.positions[0], glm::vec3(0.0f));
    EXPECT_EQ(mesh.positions[1], glm::vec3(1.0f, 0.0f, 0.0f));  // rim vertex 0 on +x
    for (size_t k = 1; k < mesh.positions.size(); ++k) {
      EXPECT_NEAR(glm::length(mesh.positions[k]), 1.0f, 1e-6f);
      EXPECT_EQ(mesh.positions[k].z, 0.0f);
    }
    for (const glm::uvec3& t : mesh.triangles) EXPECT_NEAR(normalOf(mesh, t).z, 1.0, 1e-6);
    // The inscribed regular polygon: n/2 sin(2 pi / n); a square is 2, a triangle 3 sqrt(3)/4.
    EXPECT_NEAR(meshArea(mesh.positions, mesh.triangles), 0.5 * segments * std::sin(2 * M_PI / segments), 1e-6);
    // The rim closes: every rim vertex is used by exactly two triangles.
    std::map<uint32_t, int> uses;
    for (const glm::uvec3& t : mesh.triangles) ++uses[t.y], ++uses[t.z];
    for (uint32_t k = 1; k <= segments; ++k) EXPECT_EQ(uses[k], 2) << "rim vertex " << k;
  }
  EXPECT_NEAR(meshArea(makeDisk(4).positions, makeDisk(4).triangles), 2.0, 1e-6);
}

TEST(Primitives, FlatHeightfieldFacesUp) {
  const TriangleMesh mesh = makeHeightfield(4, 3, 3.0f, 2.0f, std::vector<float>(12, 0.5f));
  EXPECT_EQ(mesh.triangles.size(), 2u * 3u * 2u);
  EXPECT_NEAR(meshArea(mesh.positions, mesh.triangles), 6.0, 1e-6);
  for (const glm::uvec3& t : mesh.triangles) EXPECT_NEAR(normalOf(mesh, t).y, 1.0, 1e-6);
  // Vertex (i, j) = heights[j * nx + i] at x = -sx/2 + i sx/(nx-1), z = -sz/2 + j sz/(nz-1).
  EXPECT_EQ(mesh.positions[0], glm::vec3(-1.5f, 0.5f, -1.0f));
  EXPECT_EQ(mesh.positions[3], glm::vec3(1.5f, 0.5f, -1.0f));
  EXPECT_EQ(mesh.positions[11], glm::vec3(1.5f, 0.5f, 1.0f));
}

TEST(Primitives, SlopedHeightfieldAreaAndHeightsOrder) {
  // y = k x over a 2 x 2 patch: area 4 sqrt(1 + k^2), normals (-k, 1, 0) / sqrt(1 + k^2).
  const float k = 0.75f;
  const uint32_t nx = 5, nz = 3;
  std::vector<float> heights;
  for (uint32_t j = 0; j < nz; ++j)
    for (uint32_t i = 0; i < nx; ++i) heights.push_back(k * (-1.0f + 2.0f * float(i) / float(nx - 1)));
  const TriangleMesh mesh = makeHeightfield(nx, nz, 2.0f, 2.0f, heights);
  EXPECT_NEAR(meshArea(mesh.positions, mesh.triangles), 4.0 * std::sqrt(1.0 + k * k), 1e-5);
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 n = normalOf(mesh, t);
    EXPECT_NEAR(n.x, -k / std::sqrt(1.0 + k * k), 1e-6);
    EXPECT_NEAR(n.y, 1.0 / std::sqrt(1.0 + k * k), 1e-6);
  }
}

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

void expectNear(glm::vec3 a, glm::vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-6f);
  EXPECT_NEAR(a.y, b.y, 1e-6f);
  EXPECT_NEAR(a.z, b.z, 1e-6f);
}

TEST(Primitives, TransformRotatesXThenYThenZAboutWorldAxes) {
  expectNear(apply(composeTransform({}, {90, 0, 0}, glm::vec3(1)), {0, 1, 0}), {0, 0, 1});
  expectNear(apply(composeTransform({}, {0, 90, 0}, glm::vec3(1)), {0, 0, 1}), {1, 0, 0});
  expectNear(apply(composeTransform({}, {0, 0, 90}, glm::vec3(1)), {1, 0, 0}), {0, 1, 0});
  // X first: (0,1,0) -> (0,0,1) -> about Y -> (1,0,0). Y first would give (0,0,1).
  expectNear(apply(composeTransform({}, {90, 90, 0}, glm::vec3(1)), {0, 1, 0}), {1, 0, 0});
  // Y before Z: (0,0,1) -> (1,0,0) -> about Z -> (0,1,0). Z first would give (1,0,0).
  expectNear(apply(composeTransform({}, {0, 90, 90}, glm::vec3(1)), {0, 0, 1}), {0, 1, 0});
}

TEST(Primitives, TransformScalesThenRotatesThenTranslates) {
  const glm::mat4 m = composeTransform({1, 2, 3}, {0, 0, 90}, {2, 1, 1});
  expectNear(apply(m, {1, 0, 0}), glm::vec3(0, 2, 0) + glm::vec3(1, 2, 3));
  expectNear(apply(m, {0, 1, 0}), glm::vec3(-1, 0, 0) + glm::vec3(1, 2, 3));
}

TEST(Primitives, TransformKeepsFrontFaceUnderRotationAndMirroring) {
  TriangleMesh floor = makeRectangle();
  transformMesh(floor, composeTransform({0, 0, 0}, {-90, 0, 0}, glm::vec3(2)));
  for (const glm::uvec3& t : floor.triangles) EXPECT_NEAR(normalOf(floor, t).y, 1.0, 1e-6);
  EXPECT_NEAR(meshArea(floor.positions, floor.triangles), 16.0, 1e-5);

  // Mirroring x maps the +z-facing square onto itself: it must still face +z.
  TriangleMesh mirrored = makeRectangle();
  transformMesh(mirrored, composeTransform({}, {}, {-1, 1, 1}));
  for (const glm::uvec3& t : mirrored.triangles) EXPECT_NEAR(normalOf(mirrored, t).z, 1.0, 1e-12);
  // Mirroring z turns the front face to -z.
  TriangleMesh flipped = makeRectangle();
  transformMesh(flipped, composeTransform({}, {}, {1, 1, -1}));
  for (const glm::uvec3& t : flipped.triangles) EXPECT_NEAR(normalOf(flipped, t).z, -1.0, 1e-12);
  // A mirrored cube still faces outward.
  TriangleMesh cube = makeCube();
  transformMesh(cube, composeTransform({}, {}, {1, -1, 1}));
  for (const glm::uvec3& t : cube.triangles) EXPECT_GT(glm::dot(normalOf(cube, t), centroidOf(cube, t)), 0.0);
}

}  // namespace
}  // namespace vktg
