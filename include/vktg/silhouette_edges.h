// The edges the visibility-boundary (edge) pass samples: every edge of the scene's triangles that
// can be a silhouette from some direction. CPU only, so tests check it without a device.
#pragma once
#include <vector>

#include "vktg/gpu/shared.h"
#include "vktg/prepared_scene.h"

namespace vktg {

// Edges are matched by the exact positions of their ends (meshes that duplicate vertices along a
// seam still share the edge), so a crease between two faces is found once. Kept: boundary edges
// (one face) and creases whose faces are not coplanar; an edge of three or more faces (non-manifold)
// is kept as the crease of its first two. Dropped: flat creases, which no line can graze without
// entering a face on both sides. Degenerate (zero-length) edges are dropped. Edges come in order of
// the bit patterns of their ends' positions, lower end first (p0), an edge's faces in the order
// the triangles are listed: an edge's index is part of every edge sample. A CDF in 32-bit fixed
// point (inward0.w) selects edges, pmf (exactly the edge's share of it) in inward1.w:
// proportionally to length, or, when `movingVertex` (per vertex of `prepared`) marks some edges as
// moving and others not, half the mass on the moving edges by length and half on all edges by
// length. A static edge still carries the term where an end of its boundary segment moves (a
// moving light, x_a or x_b on a moving shape), hence the defensive half; a moving edge is where
// the term usually is.
std::vector<gpu::GpuEdge> silhouetteEdges(const PreparedScene& prepared, const std::vector<bool>& movingVertex = {});

// The same edges with, per edge, the vertex opposite it in each of its first two faces (x, y; ~0 for
// none), which is what moving the list with its vertices needs, and those faces' triangles in the
// prepared scene's leaf order (z, w; ~0 for none), which the edge pass tests a ray beside the edge
// against before it traverses the BVH. Flat creases with a vertex that
// `deformingVertex` marks (per vertex; displaced on its own, not with its whole shape) are kept
// too: deformation can fold them into silhouettes (a heightfield starting flat). Rigid motion
// never folds a crease.
struct EdgeList {
  std::vector<gpu::GpuEdge> edges;
  std::vector<glm::uvec4> faces;
};
EdgeList edgeList(const PreparedScene& prepared, const std::vector<bool>& movingVertex,
                  const std::vector<bool>& deformingVertex);

// The share of the selection mass silhouetteEdges puts on moving edges alone.
inline constexpr double kMovingEdgeShare = 0.5;

}  // namespace vktg
