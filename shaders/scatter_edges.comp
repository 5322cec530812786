#version 460
#extension GL_GOOGLE_include_directive : require
// Pass scatter_edges (adjoint of the edge term): finishes a batch of edge samples. A slot's
// derivative is its light-side value times the factor sY (v_y . n_p) + sA (v_a . n_p) + sB (v_b . n_p)
// of its EdgeRecord (lib/edge.glsl), linear in the velocities of the edge's ends, of x_a and of x_b.
// So with A = sum_k a_k(pixel) value_k, the slot adds A sY n_p to the edge point y (split between
// the edge's vertices as (1 - t, t)), A sA n_p to x_a (a material point, or a first hit on its
// camera ray) and A sB n_p to x_b (a material point or a point light's position).
// Reads: paths (pixel), pathAccum, edge records, edges. Writes: gradient accumulators.
// Dispatch: ceil(slots of the batch / kWorkgroupSize); push.args.w: slots in the batch.
#define VKTG_ADJOINT 1
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/specialization.glsl"
#include "lib/path.glsl"
#include "lib/edge.glsl"
#include "lib/adjoint.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint slot = gl_GlobalInvocationID.x;
  if (slot >= push.args.w) return;
  EdgeRecord r = edgeRecords[slot];
  uint pixel = paths[slot].ids.x;
  if (r.normalScale.w == 0.0 || pixel == kNoPixel) return;
  setViewOfPath(paths[slot]);
  uint layers = frame.gateInfo.y;
  float weight = 0.0;
  for (uint k = 0u; k < layers; ++k) weight += adjointOf(pixel, k) * pathAccum[slot * layers + k];
  if (isnan(weight) || isinf(weight)) {
    ++scatterNonFinite;  // counted as the pass ends
    return;
  }
  if (weight == 0.0) return;
  vec3 np = r.normalScale.xyz;
  if (differentiates(kAdjointVertices)) {
    GpuEdge e = edges[floatBitsToUint(r.ends.w)];
    vec3 y = weight * r.normalScale.w * np;
    scatterVertex(floatBitsToUint(e.p0.w), (1.0 - r.ends.x) * y);
    scatterVertex(floatBitsToUint(e.p1.w), r.ends.x * y);
  }
  if (r.endA.x != 0xffffffffu) {
    VertexAdjoint a = noAdjoint();
    a.position = weight * r.ends.y * np;
    scatterSurfaceAdjoint(r.endA.x, uintBitsToFloat(r.endA.yz), a, r.endA.w != 0u);
  }
  if (r.endB.w != 0xffffffffu) {
    scatterPointLight(r.endB.w, 0.0, weight * r.ends.z * np);
  } else if (r.endB.x != 0xffffffffu) {
    VertexAdjoint b = noAdjoint();
    b.position = weight * r.ends.z * np;
    scatterSurfaceAdjoint(r.endB.x, uintBitsToFloat(r.endB.yz), b, false);
  }
}
