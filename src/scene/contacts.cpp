#include "scene/contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "vktg/bvh.h"

namespace vktg {
namespace {

using glm::dvec3;

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
  void add(glm::vec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  Box grown(float by) const { return {lo - glm::vec3(by), hi + glm::vec3(by)}; }
  bool meets(const Box& o) const {
    return glm::all(glm::lessThanEqual(lo, o.hi)) && glm::all(glm::lessThanEqual(o.lo, hi));
  }
  Box intersection(const Box& o) const { return {glm::max(lo, o.lo), glm::min(hi, o.hi)}; }
  bool contains(glm::vec3 p) const { return glm::all(glm::lessThanEqual(lo, p)) && glm::all(glm::lessThanEqual(p, hi)); }
};

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection 5.1.5).
dvec3 closestOnTriangle(dvec3 p, dvec3 a, dvec3 b, dvec3 c) {
  dvec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  dvec3 bp = p - b;
  double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  dvec3 cp = p - c;
  double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Whether segment p -> q passes through triangle (a, b, c) with both ends farther than `tolerance`
// from its plane, on opposite sides: a crossing, not a touch.
bool crossesTriangle(dvec3 p, dvec3 q, dvec3 a, dvec3 b, dvec3 c, double tolerance) {
  dvec3 n = glm::cross(b - a, c - a);
  double area = glm::length(n);
  if (!(area > 0)) return false;
  n /= area;
  double sp = glm::dot(p - a, n), sq = glm::dot(q - a, n);
  if (!((sp > tolerance && sq < -tolerance) || (sp < -tolerance && sq > tolerance))) return false;
  dvec3 x = p + (q - p) * (sp / (sp - sq));
  // Inside, farther than the tolerance from each of its edges: a segment through an edge of the
  // triangle (where a wall's edge rests on the next wall) touches it, it does not cross it.
  auto inside = [&](dvec3 from, dvec3 to) {
    return glm::dot(glm::cross(to - from, x - from), n) > tolerance * glm::length(to - from);
  };
  return inside(a, b) && inside(b, c) && inside(c, a);
}

struct SceneGeometry {
  const PreparedScene& prepared;
  std::vector<Box> boxes;                                       // per shape
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> edges;  // per shape: vertex pairs, unique

  SceneGeometry(const PreparedScene& p) : prepared(p), boxes(p.shapes.size()), edges(p.shapes.size()) {
    for (size_t i = 0; i < p.triangleVerts.size(); ++i) {
      const glm::uvec4 t = p.triangleVerts[i];
      for (uint32_t k = 0; k < 3; ++k) boxes[t.w].add(position(t[k]));
    }
  }
  glm::vec3 position(uint32_t vertex) const { return glm::vec3(prepared.vertices[vertex]); }

  const std::vector<std::pair<uint32_t, uint32_t>>& edgesOf(uint32_t shape) {
    auto& list = edges[shape];
    if (!list.empty()) return list;
    for (const glm::uvec4& t : prepared.triangleVerts) {
      if (t.w != shape) continue;
      for (uint32_t k = 0; k < 3; ++k) list.emplace_back(std::minmax(t[k], t[(k + 1) % 3]));
    }
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    return list;
  }

  std::vector<uint32_t> verticesOf(uint32_t shape) {
    std::vector<uint32_t> list;
    for (auto [i, j] : edgesOf(shape)) {
      list.push_back(i);
      list.push_back(j);
    }
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    return list;
  }

  // The triangles of `shape` near box `b`.
  template <class Visit>
  void forEachTriangleOf(uint32_t shape, const Box& b, Visit visit) const {
    forEachTriangleNearBox(prepared.bvh, b.lo, b.hi, [&](uint32_t i) {
      const glm::uvec4 t = prepared.triangleVerts[i];
      if (t.w == shape) visit(dvec3(position(t.x)), dvec3(position(t.y)), dvec3(position(t.z)));
    });
  }

  double distanceTo(uint32_t shape, dvec3 p, float tolerance) const {
    Box b;
    b.add(glm::vec3(p));
    double best = std::numeric_limits<double>::infinity();
    forEachTriangleOf(shape, b.grown(tolerance), [&](dvec3 a, dvec3 bb, dvec3 c) {
      best = std::min(best, glm::length(p - closestOnTriangle(p, a, bb, c)));
    });
    return best;
  }
};

// The edges of `shape` that rest on or cross `other`, within `region`.
ShapeContact contactOf(SceneGeometry& g, uint32_t shape, uint32_t other, const Box& region, float tolerance) {
  ShapeContact c;
  c.shape = shape;
  c.other = other;
  for (auto [i, j] : g.edgesOf(shape)) {
    const glm::vec3 p = g.position(i), q = g.position(j);
    Box edgeBox;
    edgeBox.add(p);
    edgeBox.add(q);
    if (!edgeBox.meets(region)) continue;
    const dvec3 a(p), b(q);
    if (g.distanceTo(other, a, tolerance) <= tolerance && g.distanceTo(other, b, tolerance) <= tolerance &&
        g.distanceTo(other, 0.5 * (a + b), tolerance) <= tolerance) {
      ++c.restingEdges;
      continue;
    }
    bool crosses = false;
    g.forEachTriangleOf(other, edgeBox.grown(tolerance), [&](dvec3 t0, dvec3 t1, dvec3 t2) {
      crosses = crosses || crossesTriangle(a, b, t0, t1, t2, tolerance);
    });
    if (crosses) ++c.crossingEdges;
  }
  for (uint32_t v : g.verticesOf(shape))
    if (region.contains(g.position(v)) && g.distanceTo(other, dvec3(g.position(v)), tolerance) <= tolerance)
      ++c.touchingVertices;
  return c;
}

}  // namespace

std::vector<ShapeContact> findContacts(const PreparedScene& prepared, const std::vector<bool>& movingShapes,
                                       float tolerance) {
  SceneGeometry g(prepared);
  std::vector<ShapeContact> contacts;
  const uint32_t shapes = uint32_t(prepared.shapes.size());
  auto moves = [&](uint32_t s) { return s < movingShapes.size() && movingShapes[s]; };
  for (uint32_t s = 0; s < shapes; ++s) {
    for (uint32_t o = s + 1; o < shapes; ++o) {
      if (!moves(s) && !moves(o)) continue;
      const Box a = g.boxes[s].grown(tolerance), b = g.boxes[o].grown(tolerance);
      if (!a.meets(b)) continue;
      const Box region = a.intersection(b);
      ShapeContact forward = contactOf(g, s, o, region, tolerance), backward = contactOf(g, o, s, region, tolerance);
      // Shapes that cross are one interpenetration, whichever one's edges pass through the other.
      if (forward.crossingEdges + backward.crossingEdges > 0) {
        contacts.push_back({s, o, 0, forward.crossingEdges + backward.crossingEdges, 0});
        continue;
      }
      for (const ShapeContact& c : {forward, backward})
        if (c.restingEdges + c.touchingVertices > 0) contacts.push_back(c);
    }
  }
  return contacts;
}

std::vector<std::string> describeContacts(const Scene& scene, const std::vector<ShapeContact>& contacts) {
  std::vector<std::string> lines;
  for (const ShapeContact& c : contacts) {
    const std::string a = "'" + scene.shapes.at(c.shape).name + "'", b = "'" + scene.shapes.at(c.other).name + "'";
    if (c.crossingEdges > 0) {
      lines.push_back("warning: " + a + " and " + b + " interpenetrate (" + std::to_string(c.crossingEdges) +
                      " edges of one pass through the other): the curve where their surfaces cross moves, "
                      "and no pass samples it, so its share of the derivative is missing (docs/theory.md 3.3, Contacts)");
    } else {
      const std::string what = c.restingEdges > 0 ? std::to_string(c.restingEdges) + " edges of " + a + " lie on "
                                                  : std::to_string(c.touchingVertices) + " vertices of " + a + " touch ";
      lines.push_back("warning: contact: " + what + b +
                      ": the edge pass counts the silhouettes the camera sees of them directly, but not what the "
                      "contact changes deeper in a path (points of " + b + " that " + a +
                      " covers or uncovers as it moves), and the interior term's samples near the contact are "
                      "heavy-tailed: check against vktg fd over several seeds (docs/theory.md 3.3, Contacts)");
    }
  }
  return lines;
}

}  // namespace vktg
