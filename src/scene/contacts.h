// Where shapes touch or cross (docs/theory.md 3.3, "Contacts"): the edges of one shape that lie on
// another's surface (a box resting on a floor, a wall's edge on the next wall) or pass through it
// (interpenetrating shapes). The derivative passes treat neither specially; `vktg grad --explain`
// and `vktg optimize --explain` name them, with what that means for the derivative.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {

struct ShapeContact {
  uint32_t shape = 0, other = 0;  // scene.shapes indices: edges of `shape` on or through `other`
  uint32_t restingEdges = 0;      // edges whose ends and midpoint lie within the tolerance of `other`
  uint32_t crossingEdges = 0;     // edges of either shape that pass through a triangle of the other
  uint32_t touchingVertices = 0;  // vertices within the tolerance of `other` (a sphere's lowest point)
};

// The contacts between pairs of shapes of which at least one moves (`movingShapes`, per shape), from
// the prepared scene's triangles and BVH; `tolerance` is the distance (m) within which an edge lies
// on a surface (the renderer's ray epsilon). Only edges inside the box where the two shapes' boxes
// overlap are tested, so a scene whose moving shapes touch nothing costs a box test per pair.
std::vector<ShapeContact> findContacts(const PreparedScene& prepared, const std::vector<bool>& movingShapes,
                                       float tolerance);

// Shapes that cross are one entry (crossingEdges > 0, the other counts 0); otherwise each direction
// in which edges or vertices of one lie on the other is an entry of its own.
// One line per contact for --explain: which shapes, how many edges, and what the derivative passes
// do with it.
std::vector<std::string> describeContacts(const Scene& scene, const std::vector<ShapeContact>& contacts);

}  // namespace vktg
