// The edge list of the visibility-boundary pass (vktg/silhouette_edges.h): which edges can be
// silhouettes, their face directions, and the selection CDF by length.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "vktg/silhouette_edges.h"

namespace vktg {
namespace {

Scene sceneWith(const std::string& shapes) {
  std::string text = R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "lights": [{"type": "point", "position": [0, 2, 2], "intensity": 1}],
    "shapes": [)" + shapes + "]}";
  return parseSceneJson(text, "test.json", ".");
}

double lengthOf(const gpu::GpuEdge& e) { return glm::length(glm::vec3(e.p1) - glm::vec3(e.p0)); }

constexpr double kSelectionScale = 4294967296.0;  // 2^32 selection numbers

// How many of the 2^32 selection numbers select each edge, as the sampler reads the CDF: edge i
// owns [end of edge i-1, end of edge i), the last edge's end (2^32) stored as 0.
std::vector<uint64_t> selectionWidths(const std::vector<gpu::GpuEdge>& edges) {
  std::vector<uint64_t> widths;
  uint64_t start = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    const uint64_t end = i + 1 == edges.size() ? uint64_t(kSelectionScale) : std::bit_cast<uint32_t>(edges[i].inward0.w);
    EXPECT_GT(end, start) << "edge " << i << " is never selected";
    widths.push_back(end - start);
    start = end;
  }
  EXPECT_EQ(std::bit_cast<uint32_t>(edges.back().inward0.w), 0u);
  return widths;
}

// The selection probability the sampler gives each edge is the pmf its weight divides by (to float
// rounding of the stored pmf); both are the edge's `expected` share to within the rounding of the
// two ends of its interval (half a selection number each) and of the CDF summed in double, plus
// `given` numbers that edges too short for one took from the others.
void expectSelectionMatches(const std::vector<gpu::GpuEdge>& edges, const std::vector<double>& expected, double given = 0) {
  const std::vector<uint64_t> widths = selectionWidths(edges);
  double pmfSum = 0;
  for (size_t i = 0; i < edges.size(); ++i) {
    const double selected = double(widths[i]) / kSelectionScale;
    EXPECT_NEAR(edges[i].inward1.w, selected, 6e-8 * selected) << "edge " << i;
    EXPECT_NEAR(selected, expected[i], (1.5 + given) / kSelectionScale) << "edge " << i;
    pmfSum += edges[i].inward1.w;
  }
  EXPECT_NEAR(pmfSum, 1.0, 1e-5);
}

// Selection by length; face directions unit and perpendicular to the edge.
void expectValidCdf(const std::vector<gpu::GpuEdge>& edges, double given = 0) {
  double total = 0;
  std::vector<double> share;
  for (const gpu::GpuEdge& e : edges) total += lengthOf(e);
  for (const gpu::GpuEdge& e : edges) {
    share.push_back(lengthOf(e) / total);
    glm::vec3 along = glm::normalize(glm::vec3(e.p1) - glm::vec3(e.p0));
    EXPECT_NEAR(glm::length(glm::vec3(e.inward0)), 1.0, 1e-5);
    EXPECT_NEAR(glm::dot(glm::vec3(e.inward0), along), 0.0, 1e-5);
  }
  expectSelectionMatches(edges, share, given);
}

TEST(SilhouetteEdges, RectangleKeepsItsRimAndDropsItsDiagonal) {
  Scene scene = sceneWith(R"({"name": "r", "type": "rectangle", "material": "m", "transform": {"scale": 2}})");
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  ASSERT_EQ(edges.size(), 4u);  // the two triangles' shared diagonal is a flat crease
  for (const gpu::GpuEdge& e : edges) {
    EXPECT_EQ(glm::length(glm::vec3(e.inward1)), 0.0f) << "a rim edge has one face";
    EXPECT_NEAR(lengthOf(e), 4.0, 1e-5);  // scale 2 of the unit-half-size square
    // The face direction points into the rectangle: towards its centre.
    glm::vec3 mid = 0.5f * (glm::vec3(e.p0) + glm::vec3(e.p1));
    EXPECT_GT(glm::dot(glm::vec3(e.inward0), -mid), 0.0f);
  }
  expectValidCdf(edges);
}

// Half a million creases of a bumpy heightfield, about nine thousand selection numbers each. (A
// float CDF drawn with 24-bit numbers gave them about 35 steps each and chose some of them half as
// often again as their pmf said: a float CDF fails this test.)
TEST(SilhouetteEdges, SelectionMatchesThePmfAtHalfAMillionEdges) {
  const int n = 400;
  std::string heights;
  for (int i = 0; i < n * n; ++i) heights += (i ? ", " : "") + std::to_string(0.1 * std::sin(0.37 * i));
  Scene scene = sceneWith(R"({"name": "ground", "type": "heightfield", "resolution": [400, 400], "size": [2, 2],
    "material": "m", "heights": [)" + heights + "]}");
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  EXPECT_GT(edges.size(), 400000u);
  expectValidCdf(edges);
}

// An edge whose share of the length is below one selection number (2^-32) still gets one.
TEST(SilhouetteEdges, AnEdgeShorterThanOneSelectionNumberIsStillSelected) {
  Scene scene = sceneWith(R"({"name": "big", "type": "rectangle", "material": "m", "transform": {"scale": 1e5}},
    {"name": "speck", "type": "rectangle", "material": "m", "transform": {"translate": [0, 0, 1], "scale": 1e-6}})");
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  ASSERT_EQ(edges.size(), 8u);
  expectValidCdf(edges, 4);  // the speck's four edges take one number each
  for (const gpu::GpuEdge& e : edges)
    if (lengthOf(e) < 1.0) EXPECT_FLOAT_EQ(e.inward1.w, float(1.0 / kSelectionScale));
}

TEST(SilhouetteEdges, CubeKeepsItsTwelveCreases) {
  Scene scene = sceneWith(R"({"name": "c", "type": "cube", "material": "m"})");
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  ASSERT_EQ(edges.size(), 12u);  // face diagonals are flat creases
  for (const gpu::GpuEdge& e : edges) {
    glm::vec3 i0(e.inward0), i1(e.inward1);
    EXPECT_NEAR(glm::length(i1), 1.0, 1e-5) << "every cube edge joins two faces";
    EXPECT_NEAR(glm::dot(i0, i1), 0.0, 1e-5) << "cube faces meet at right angles";
  }
  expectValidCdf(edges);
}

TEST(SilhouetteEdges, SeparateShapesSharingAnEdgePositionAreOneCrease) {
  // A wall standing on the rectangle's rim at x = 1 (its own vertices, same positions): one
  // crease at 90 degrees, not two boundary edges.
  Scene scene = sceneWith(R"({"name": "a", "type": "rectangle", "material": "m"})");
  Shape wall;
  wall.name = "wall";
  wall.positions = {{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.shapes.push_back(wall);
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  int creases = 0;
  for (const gpu::GpuEdge& e : edges) creases += glm::length(glm::vec3(e.inward1)) > 0.0f;
  EXPECT_EQ(edges.size(), 7u);
  EXPECT_EQ(creases, 1);
  expectValidCdf(edges);
}

TEST(SilhouetteEdges, MovingEdgesGetHalfTheMass) {
  // A 4 x 4 rectangle (rim 16) and a 1 x 1 one beside it (rim 4) whose vertices move.
  Scene scene = sceneWith(R"({"name": "big", "type": "rectangle", "material": "m", "transform": {"scale": 2}},
    {"name": "small", "type": "rectangle", "material": "m", "transform": {"translate": [5, 0, 0], "scale": 0.5}})");
  PreparedScene prepared = prepareScene(scene);
  std::vector<bool> moving(prepared.vertices.size(), false);
  for (size_t v = 0; v < moving.size(); ++v) moving[v] = prepared.vertices[v].x > 3.0f;
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepared, moving);
  ASSERT_EQ(edges.size(), 8u);
  std::vector<double> expected;
  double movingMass = 0;
  for (const gpu::GpuEdge& e : edges) {
    bool onSmall = e.p0.x > 3.0f;
    // Length share of 20 for the static half; the small rim's share of its 4 for the moving half.
    expected.push_back((1.0 - kMovingEdgeShare) * lengthOf(e) / 20.0 + (onSmall ? kMovingEdgeShare * lengthOf(e) / 4.0 : 0.0));
    if (onSmall) movingMass += e.inward1.w;
  }
  expectSelectionMatches(edges, expected);
  EXPECT_NEAR(movingMass, kMovingEdgeShare + (1.0 - kMovingEdgeShare) * 4.0 / 20.0, 1e-5);
  // Everything moving, or nothing: selection by length.
  expectValidCdf(silhouetteEdges(prepared, std::vector<bool>(moving.size(), true)));
  expectValidCdf(silhouetteEdges(prepared, std::vector<bool>(moving.size(), false)));
}

// The order the edges come in is part of every edge sample (the CDF's index), so it must not depend
// on how the list is built: by the bit patterns of the ends' positions, lower end first.
TEST(SilhouetteEdges, EdgesComeOnceEachInOrderOfTheirEndsPositions) {
  Scene scene = sceneWith(R"({"name": "c", "type": "cube", "material": "m"})");
  Shape hill;
  hill.name = "hill";
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) hill.positions.push_back({i - 2.5f, 0.3f * std::sin(1.7f * i * j), j - 2.5f});
  // Triangles listed in a scrambled order: the list's order must not follow it.
  for (int q = 0; q < (n - 1) * (n - 1); ++q) {
    int cell = (q * 7) % ((n - 1) * (n - 1)), i = cell % (n - 1), j = cell / (n - 1);
    uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
    hill.triangles.push_back({a, c, b});
    hill.triangles.push_back({b, c, d});
  }
  scene.shapes.push_back(hill);
  std::vector<gpu::GpuEdge> edges = silhouetteEdges(prepareScene(scene));
  ASSERT_GT(edges.size(), 12u + 4u * (n - 1));
  auto key = [](glm::vec4 p) {
    std::array<uint32_t, 3> k;
    std::memcpy(k.data(), &p, sizeof k);
    return k;
  };
  for (size_t e = 0; e < edges.size(); ++e) {
    EXPECT_LT(key(edges[e].p0), key(edges[e].p1)) << "edge " << e << ": the lower end first";
    if (e > 0)
      EXPECT_LT(std::make_pair(key(edges[e - 1].p0), key(edges[e - 1].p1)), std::make_pair(key(edges[e].p0), key(edges[e].p1)))
          << "edges " << e - 1 << " and " << e << " out of order, or one edge twice";
  }
  expectValidCdf(edges);
}

// Each face of an edge named by its triangle in leaf order (what sample_edges tests a ray beside the
// edge against): a triangle with both of the edge's ends and the face's opposite vertex; ~0 where
// the edge has no second face.
void expectFacesNameTheirTriangles(const PreparedScene& prepared, const EdgeList& list) {
  ASSERT_EQ(list.faces.size(), list.edges.size());
  for (size_t e = 0; e < list.edges.size(); ++e) {
    const glm::uvec4& faces = list.faces[e];
    const bool twoFaces = glm::length(glm::vec3(list.edges[e].inward1)) > 0.0f;
    for (int face = 0; face < 2; ++face) {
      const uint32_t opposite = face == 0 ? faces.x : faces.y, triangle = face == 0 ? faces.z : faces.w;
      if (face == 1 && !twoFaces) {
        EXPECT_EQ(triangle, 0xffffffffu) << "edge " << e << " has one face";
        continue;
      }
      ASSERT_LT(triangle, prepared.triangleVerts.size()) << "edge " << e << ", face " << face;
      std::vector<glm::vec3> corners;
      for (uint32_t v : {prepared.triangleVerts[triangle].x, prepared.triangleVerts[triangle].y, prepared.triangleVerts[triangle].z})
        corners.push_back(glm::vec3(prepared.vertices[v]));
      for (glm::vec3 p : {glm::vec3(list.edges[e].p0), glm::vec3(list.edges[e].p1), glm::vec3(prepared.vertices[opposite])})
        EXPECT_NE(std::find(corners.begin(), corners.end(), p), corners.end())
            << "edge " << e << ", face " << face << ": triangle " << triangle << " lacks a corner";
    }
  }
}

TEST(SilhouetteEdges, EveryFaceIsNamedByItsTriangle) {
  Scene scene = sceneWith(R"({"name": "c", "type": "cube", "material": "m", "transform": {"rotate": [20, 30, 0]}},
                             {"name": "r", "type": "rectangle", "material": "m", "transform": {"translate": [0, -2, 0]}})");
  const PreparedScene prepared = prepareScene(scene);
  const EdgeList list = edgeList(prepared, {}, {});
  ASSERT_EQ(list.edges.size(), 16u);
  expectFacesNameTheirTriangles(prepared, list);
}

TEST(SilhouetteEdges, AnEdgeOfThreeFacesIsTheCreaseOfTheFirstTwoListed) {
  // Three fins on the edge from (0,0,0) to (0,0,1), no two of them coplanar.
  Scene scene = sceneWith(R"({"name": "far", "type": "rectangle", "material": "m", "transform": {"translate": [9, 9, 9]}})");
  Shape fins;
  fins.name = "fins";
  fins.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0.5f}, {0, 1, 0.5f}, {-0.6f, -0.8f, 0.5f}};
  fins.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  scene.shapes.push_back(fins);
  PreparedScene prepared = prepareScene(scene);
  // The fins' tips in the order the prepared scene lists their triangles (the BVH's).
  std::vector<glm::vec3> tips;
  for (const glm::uvec4& t : prepared.triangleVerts)
    for (uint32_t v : {t.x, t.y, t.z})
      if (glm::vec3(prepared.vertices[v]).z == 0.5f) tips.push_back(glm::vec3(prepared.vertices[v]));
  ASSERT_EQ(tips.size(), 3u);
  EdgeList list = edgeList(prepared, {}, {});
  int found = 0;
  for (size_t e = 0; e < list.edges.size(); ++e) {
    const gpu::GpuEdge& edge = list.edges[e];
    if (!(glm::vec3(edge.p0) == glm::vec3(0, 0, 0) && glm::vec3(edge.p1) == glm::vec3(0, 0, 1))) continue;
    ++found;
    const glm::vec3 first = tips[0] - glm::vec3(0, 0, 0.5f), second = tips[1] - glm::vec3(0, 0, 0.5f);
    EXPECT_NEAR(glm::distance(glm::vec3(edge.inward0), glm::normalize(first)), 0.0, 1e-6);
    EXPECT_NEAR(glm::distance(glm::vec3(edge.inward1), glm::normalize(second)), 0.0, 1e-6);
    EXPECT_EQ(glm::vec3(prepared.vertices[list.faces[e].x]), tips[0]);
    EXPECT_EQ(glm::vec3(prepared.vertices[list.faces[e].y]), tips[1]);
  }
  EXPECT_EQ(found, 1);
  expectFacesNameTheirTriangles(prepared, list);
}

}  // namespace
}  // namespace vktg
