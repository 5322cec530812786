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

// Edge by its CDF (proportional to length).
uint selectEdge(float u) {
  uint lo = 0u, hi = frame.edgeInfo.x - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (edges[mid].inward0.w > u) hi = mid; else lo = mid + 1u;
  }
  return lo;
}

// Whether a line through the edge along `dir` grazes it as a silhouette (both faces on one side
// of the plane spanned by the edge and `dir`); then `np` is that plane's unit normal pointing away
// from the faces and sinPhi = |edge x dir| / |edge|.
bool silhouettePlane(GpuEdge e, vec3 dir, out vec3 np, out float sinPhi) {
  vec3 along = normalize(e.p1.xyz - e.p0.xyz);
  vec3 c = cross(along, dir);
  sinPhi = length(c);
  np = vec3(0.0);
  if (!(sinPhi > 1e-6)) return false;  // the line runs along the edge: no boundary crossing
  np = c / sinPhi;
  float s0 = dot(e.inward0.xyz, np), s1 = dot(e.inward1.xyz, np);
  bool boundaryEdge = dot(e.inward1.xyz, e.inward1.xyz) == 0.0;
  if (s0 == 0.0 || (!boundaryEdge && !(s0 * s1 > 0.0))) return false;
  if (s0 > 0.0) np = -np;
  return true;
}

// v_n above; vA, vB zero for an end that does not move (or moves along the segment).
float edgeNormalVelocity(vec3 vY, vec3 vA, vec3 vB, float dA, float dB, vec3 np) {
  return dot(vY, np) - (dB * dot(vA, np) + dA * dot(vB, np)) / (dA + dB);
}
#endif
