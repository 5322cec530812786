// Built-in shapes in their local frames (docs/scene-format.md) and the transform that places them.
// Winding convention everywhere: the geometric normal normalize(cross(p1 - p0, p2 - p0)) of a
// triangle (p0, p1, p2) points out of its front face, the face an emissive shape emits from.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace vktg {

struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
};

// Square [-1, 1]^2 in the xy-plane; front face +z. 4 vertices, 2 triangles, area 4.
TriangleMesh makeRectangle();
// Cube [-1, 1]^3; front faces outward. 8 shared vertices, 12 triangles, area 24.
TriangleMesh makeCube();
// Icosphere inscribed in the unit sphere: an icosahedron whose triangles are split into 4,
// `subdivisions` times (20 * 4^s triangles, vertices shared and projected onto the sphere);
// front faces outward.
TriangleMesh makeIcosphere(uint32_t subdivisions);
// Disk inscribed in the unit circle of the xy-plane: a fan of `segments` triangles (at least 3)
// around a centre vertex, rim vertex k at angle 2 pi k / segments from +x; front face +z. Area
// segments/2 * sin(2 pi / segments), slightly below pi.
TriangleMesh makeDisk(uint32_t segments);
// Grid of nx * nz vertices in the xz-plane centred at the origin, spanning sizeX * sizeZ, with
// vertex (i, j) at x = -sizeX/2 + i*sizeX/(nx-1), z = -sizeZ/2 + j*sizeZ/(nz-1),
// y = heights[j * nx + i]; front face +y. Requires nx, nz >= 2 and heights.size() == nx * nz.
TriangleMesh makeHeightfield(uint32_t nx, uint32_t nz, float sizeX, float sizeZ, const std::vector<float>& heights);

// translate * rotateZ * rotateY * rotateX * scale: rotations in degrees about the world axes,
// X first, then Y, then Z.
glm::mat4 composeTransform(glm::vec3 translate, glm::vec3 rotateDegrees, glm::vec3 scale);

// Applies `transform` to every position. A mirroring transform (negative determinant) would turn
// front faces into back faces; the winding is reversed then so the front face stays the image of
// the front face.
void transformMesh(TriangleMesh& mesh, const glm::mat4& transform);
// Whether every coordinate is finite: a transform can take finite vertices past the float range.
bool allFinite(const std::vector<glm::vec3>& positions);

double meshArea(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles);

}  // namespace vktg
