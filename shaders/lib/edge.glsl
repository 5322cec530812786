// The visibility-boundary (edge) term, THEORY.md §3: paths with one segment x_a -> x_b that
// grazes a silhouette edge at y. For a fixed x_a, Reynolds' theorem over x_b integrates the jump
// of the integrand times the normal velocity of the shadow curve; changing variables from that
// curve to the edge (and, for a surface x_a, from its area to the direction at y) collapses every
// cosine and distance into one weight:
//
//   surface x_a (direction w sampled at y with density p_w):
//       contribution = -f' sin(phi) v_n / (p_y p_w)
//   fixed x_a (camera, sensor; w = the direction from x_a to y):
//       contribution = -f' sin(phi) v_n / (|y - x_a|^2 p_y)
//
// f' is the path's contribution without the geometry term of the boundary segment (a fixed x_a
// keeps its importance per unit solid angle), p_y the density of y on the edges, phi the angle
// between the edge and w, and v_n the velocity of the edge at y relative to the segment, along the
// plane normal n_p (the side where the segment is unoccluded):
//
//   v_n = (v_y - (d_b v_a + d_a v_b) / (d_a + d_b)) . n_p,   d_a = |y - x_a|, d_b = |x_b - y|
//
// (the segment's own velocity interpolated to y: a rigid motion of everything gives 0). Moving
// towards n_p the edge blocks the segment, hence the minus sign. Behind a pinhole the first hit is
// kept on its camera ray, so a primary edge separates two images, and its jump is the difference
// of the radiance on both sides (sample_edges traces both).
// Requires lib/common.glsl and lib/bindings.glsl first.
#ifndef VKTG_EDGE_GLSL
#define VKTG_EDGE_GLSL

layout(std430, set = 0, binding = kBindingEdges) readonly buffer EdgesBlock { GpuEdge edges[]; };
layout(std430, set = 0, binding = kBindingEdgeRecords) buffer EdgeRecordsBlock { EdgeRecord edgeRecords[]; };

// Where edge i's interval of 32-bit selection numbers ends (GpuEdge.inward0.w); the last edge's
// end, 2^32, reads as 0.
uint edgeIntervalEnd(uint i) { return floatBitsToUint(edges[i].inward0.w); }

// Edge by its CDF (proportional to length) for 32 random bits `u`: the edge whose interval holds
// u, which happens with probability exactly its pmf (inward1.w). The last edge's end is never read.
uint selectEdge(uint u) {
  uint lo = 0u, hi = frame.edgeInfo.x - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (edgeIntervalEnd(mid) > u) hi = mid; else lo = mid + 1u;
  }
  return lo;
}

// Where u falls within edge `edge`'s interval, in [0, 1].
float placeInEdgeInterval(uint u, uint edge) {
  uint start = edge > 0u ? edgeIntervalEnd(edge - 1u) : 0u;
  // The width less one fits 32 bits also for a single edge (2^32 wraps to 0, minus one to 2^32 - 1).
  uint widthLessOne = edgeIntervalEnd(edge) - start - 1u;
  return float(u - start) / (float(widthLessOne) + 1.0);
}

// The plane spanned by the edge and `dir`: its unit normal `np`, sinPhi = |edge x dir| / |edge|,
// and on which side each face lies (s0, s1: the faces' inward directions along np; s1 = 0 for a
// boundary edge). False when the line runs along the edge (no boundary crossing).
bool edgePlane(GpuEdge e, vec3 dir, out vec3 np, out float sinPhi, out float s0, out float s1) {
  vec3 along = normalize(e.p1.xyz - e.p0.xyz);
  vec3 c = cross(along, dir);
  sinPhi = length(c);
  np = vec3(0.0);
  s0 = 0.0;
  s1 = 0.0;
  if (!(sinPhi > 1e-6)) return false;
  np = c / sinPhi;
  s0 = dot(e.inward0.xyz, np);
  s1 = dot(e.inward1.xyz, np);
  return true;
}

// Whether a line through the edge along `dir` grazes it as a silhouette (both faces on one side
// of the plane spanned by the edge and `dir`); then `np` is that plane's unit normal pointing away
// from the faces.
bool silhouettePlane(GpuEdge e, vec3 dir, out vec3 np, out float sinPhi) {
  float s0, s1;
  if (!edgePlane(e, dir, np, sinPhi, s0, s1)) return false;
  bool boundaryEdge = dot(e.inward1.xyz, e.inward1.xyz) == 0.0;
  if (s0 == 0.0 || (!boundaryEdge && !(s0 * s1 > 0.0))) return false;
  if (s0 > 0.0) np = -np;
  return true;
}

// Whether the line crosses a crease with a face on either side of that plane, so that both faces
// can be seen along lines beside it (THEORY.md 3.3, "Creases behind a pinhole").
bool creasePlane(GpuEdge e, vec3 dir, out vec3 np, out float sinPhi) {
  float s0, s1;
  return edgePlane(e, dir, np, sinPhi, s0, s1) && s0 * s1 < 0.0;
}

// The record of a slot whose factor is -v_n (v_n above) for the boundary segment x_a -> x_b that
// grazes edge `edge` at parameter t: the ends are filled in by the caller (recordEndA / recordEndB;
// an end left empty does not move, or moves along the segment).
EdgeRecord boundaryRecord(uint edge, float t, vec3 np, float dA, float dB) {
  EdgeRecord r;
  r.normalScale = vec4(np, -1.0);
  r.ends = vec4(t, dB / (dA + dB), dA / (dA + dB), uintBitsToFloat(edge));
  r.endA = uvec4(0xffffffffu, 0u, 0u, 0u);
  r.endB = uvec4(0xffffffffu, 0u, 0u, 0xffffffffu);
  return r;
}

// x_a at a surface point; `rayForm`: a first hit kept on its camera ray.
void recordEndA(inout EdgeRecord r, uint triangle, vec2 uv, bool rayForm) {
  r.endA = uvec4(triangle, floatBitsToUint(uv.x), floatBitsToUint(uv.y), rayForm ? 1u : 0u);
}

// x_b at a surface point (also an area-light point) or at a point light (lights[] index).
void recordEndB(inout EdgeRecord r, uint triangle, vec2 uv, uint pointLight) {
  r.endB = uvec4(triangle, floatBitsToUint(uv.x), floatBitsToUint(uv.y), pointLight);
}

// The slot factor sY (v_y . n_p) + sA (v_a . n_p) + sB (v_b . n_p) for given velocities; for a
// boundaryRecord it is -v_n.
float recordFactor(EdgeRecord r, vec3 vY, vec3 vA, vec3 vB) {
  vec3 np = r.normalScale.xyz;
  return r.normalScale.w * dot(vY, np) + r.ends.y * dot(vA, np) + r.ends.z * dot(vB, np);
}

#ifdef VKTG_LANE_INPUTS
// The slot factor for one forward-mode lane.
vec3 laneVertexVelocity(uint vertex, uint lane) {
  return vertexVelocity[lane * floatBitsToUint(frame.sceneInfo.w) + vertex].xyz;
}

vec3 laneSurfaceVelocity(uint triangle, vec2 uv, uint lane) {
  uvec4 ids = triangleVerts[triangle];
  return (1.0 - uv.x - uv.y) * laneVertexVelocity(ids.x, lane) + uv.x * laneVertexVelocity(ids.y, lane) +
         uv.y * laneVertexVelocity(ids.z, lane);
}

// A first hit on its fixed camera ray moves along the ray (geometry_dual.glsl's rayHitRate).
vec3 laneRayFormVelocity(uint triangle, vec2 uv, uint lane) {
  GpuTriangle t = loadTriangle(triangle);
  vec3 x = (1.0 - uv.x - uv.y) * t.p0.xyz + uv.x * t.p1.xyz + uv.y * t.p2.xyz;
  vec3 dir = normalize(x - cameraPosition());
  vec3 n = cross(t.p1.xyz - t.p0.xyz, t.p2.xyz - t.p0.xyz);
  return dot(n, laneSurfaceVelocity(triangle, uv, lane)) / dot(n, dir) * dir;
}

float edgeRecordFactor(EdgeRecord r, uint lane) {
  if (r.normalScale.w == 0.0) return 0.0;
  GpuEdge e = edges[floatBitsToUint(r.ends.w)];
  vec3 vY = mix(laneVertexVelocity(floatBitsToUint(e.p0.w), lane), laneVertexVelocity(floatBitsToUint(e.p1.w), lane),
                r.ends.x);
  vec3 vA = vec3(0.0);
  if (r.endA.x != 0xffffffffu) {
    vec2 uv = uintBitsToFloat(r.endA.yz);
    vA = r.endA.w != 0u ? laneRayFormVelocity(r.endA.x, uv, lane) : laneSurfaceVelocity(r.endA.x, uv, lane);
  }
  vec3 vB = vec3(0.0);
  if (r.endB.w != 0xffffffffu) {
    GpuLane info = lanes[lane];
    bool moves = info.info.x == kLaneGeometry && info.info.z == 1u && info.info.y == r.endB.w;
    vB = moves ? info.lightVelocity.xyz : vec3(0.0);
  } else if (r.endB.x != 0xffffffffu) {
    vB = laneSurfaceVelocity(r.endB.x, uintBitsToFloat(r.endB.yz), lane);
  }
  return recordFactor(r, vY, vA, vB);
}
#endif
#endif
