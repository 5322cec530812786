// Reverse mode of the path contributions for the adjoint passes (THEORY.md §7). A contribution's
// derivative with respect to θ is its value times the derivative of the log of its factors
// (every factor touches at most three consecutive vertices) plus W'(L) times the value times
// dL/dθ. Instead of carrying that along lanes, each pass adds, per contribution, the weights
//   value weight   a W(L) c    (a = d loss / d I of the pixel and layer, summed over layers)
//   length weight  a W'(L) c
// times the gradient of log F (or of a segment's length) with respect to the scene quantities F
// depends on, into fixed-point accumulators (kBindingGradient): per vertex through the triangle a
// path vertex lies on (its position and normal, the area Jacobian of its material point), per
// material, emitter, point light and the gate. Sampling densities are constants of a sample, as in
// the forward passes, so both compute the same derivative sample by sample.
// Requires VKTG_ADJOINT, lib/common.glsl, lib/bindings.glsl and lib/nee.glsl first.
#ifndef VKTG_ADJOINT_GLSL
#define VKTG_ADJOINT_GLSL
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lib/bsdf_gradient.glsl"
#include "lib/camera.glsl"
#include "lib/geometry_dual.glsl"

layout(std430, set = 0, binding = kBindingAdjointImage) readonly buffer AdjointImageBlock { float adjointImage[]; };
layout(std430, set = 0, binding = kBindingGradient) buffer GradientBlock { int64_t gradient[]; };

bool differentiates(uint targets) { return (kSpecAdjointTargetsValue & targets) != 0u; }

// What scatter() could not add in this invocation: non-finite values (and non-finite adjoint
// weights the passes meet before scattering), and values beyond the accumulators' range (the
// driver then redoes the work with a coarser scale). Every pass that includes this file must call
// countScatterFaults() as its main() ends: the faults are counted once per invocation, not per
// scatter, because a counter atomic that no lane takes still costs a loop over the lanes on a CPU.
uint scatterNonFinite = 0u, scatterOverflows = 0u;

// With few parameters, many paths add to the same accumulators (a 121-height field's vertices, the
// gate's slot): on a GPU their atomics queue on a few addresses (on an H100 the interior term's
// shadow pass took 7 times as long as the render's for as many rays; docs/benchmarks.md, sixth
// sitting). So there (kSpecScatterAggregate) the lanes of a subgroup that add
// to the same slot first sum their values and one of them adds the sum, while at least
// kAggregateMinLanes lanes share a slot; the rest add their own. The sum is taken exactly, in three
// 32-bit parts of at most 22 bits (a subgroup of up to 2^10 lanes cannot carry out of a part), and
// the accumulator receives the same integer modulo 2^64 as from the lanes one by one: the gradient
// is the same bit for bit either way.
const uint kAggregateMinLanes = 4u;

void addToAccumulator(uint slot, int64_t value) {
  if (kSpecScatterAggregateValue == 0u) {
    atomicAdd(gradient[slot], value);
    return;
  }
  for (;;) {
    uint first = subgroupBroadcastFirst(slot);
    bool shares = slot == first;
    if (subgroupBallotBitCount(subgroupBallot(shares)) < kAggregateMinLanes) break;
    if (shares) {
      uint64_t bits = uint64_t(value);
      uvec3 parts = uvec3(uint(bits & 0x3fffffUL), uint((bits >> 22) & 0x3fffffUL), uint(bits >> 44));
      uvec3 sums = subgroupAdd(parts);
      uint64_t total = uint64_t(sums.x) + (uint64_t(sums.y) << 22) + (uint64_t(sums.z) << 44);
      if (subgroupElect()) atomicAdd(gradient[slot], int64_t(total));
      return;
    }
  }
  atomicAdd(gradient[slot], value);
}

// Adds `value` to accumulator `slot` as round(value * scale): integer sums do not depend on the
// order of the adds.
void scatter(uint slot, float value) {
  if (value == 0.0) return;
  float scaled = value * frame.adjointScale.x;
  if (!(abs(scaled) < 4.0e18)) {
    if (isnan(scaled)) ++scatterNonFinite;
    else ++scatterOverflows;
    return;
  }
  addToAccumulator(slot, int64_t(round(scaled)));
}

void countScatterFaults() {
  if (scatterNonFinite > 0u) atomicAdd(counters[kCounterNonFinite], scatterNonFinite);
  if (scatterOverflows > 0u) atomicAdd(counters[kCounterGradientOverflow], scatterOverflows);
}

// A vertex has an accumulator only for the components some parameter moves vertices along
// (kAdjointVertexX/Y/Z), in x, y, z order (ParameterModel::vertexGradientStride): the others are
// neither compiled in nor stored.
void scatterVertex(uint vertex, vec3 g) {
  bool x = differentiates(kAdjointVertexX), y = differentiates(kAdjointVertexY), z = differentiates(kAdjointVertexZ);
  uint slot = frame.gradientLayout.w + (uint(x) + uint(y) + uint(z)) * vertex;
  if (x) scatter(slot++, g.x);
  if (y) scatter(slot++, g.y);
  if (z) scatter(slot, g.z);
}

void scatterGate(float g) {
  if (differentiates(kAdjointGate)) scatter(0u, g);
}

void scatterMaterial(uint material, vec3 g) {
  if (!differentiates(kAdjointMaterials)) return;
  uint slot = frame.gradientLayout.x + 3u * material;
  scatter(slot, g.x);
  scatter(slot + 1u, g.y);
  scatter(slot + 2u, g.z);
}

void scatterEmission(uint shape, float g) {
  if (differentiates(kAdjointEmission)) scatter(frame.gradientLayout.y + shape, g);
}

// A point light (lights[] index): its intensity and position.
void scatterPointLight(uint light, float intensity, vec3 position) {
  if (!differentiates(kAdjointLights)) return;
  uint slot = frame.gradientLayout.z + 4u * (light - frame.adjointInfo.x);
  scatter(slot, intensity);
  scatter(slot + 1u, position.x);
  scatter(slot + 2u, position.y);
  scatter(slot + 3u, position.z);
}

// d loss / d I of `pixel` in gate layer `layer`, divided by the samples every pixel's mean averages
// (frame.adjointScale.y: the samples per pixel, fractional where the render spreads fewer paths
// than pixels, or all samples of a splatted render's view): what one sample's contribution to the
// pixel's mean is weighted by.
float adjointOf(uint pixel, uint layer) {
  return adjointImage[layer * frame.image.x * frame.image.y + pixel] / frame.adjointScale.y;
}

// (sum_k a_k W_k(L), sum_k a_k W'_k(L)) over the layers a path of length L reaches.
vec2 adjointGateWeights(uint pixel, float len) {
  uint first, count;
  gateLayers(len, first, count);
  vec2 w = vec2(0.0);
  for (uint k = first; k < first + count; ++k) {
    float a = adjointOf(pixel, k);
    w += a * vec2(gateWeight(len, k), gateWeightSlope(len, k));
  }
  return w;
}

// sum_k a_k ΔW_k(s_j) over the layers jump j changes (path-length boundary).
float adjointJumpWeight(uint pixel, uint jump) {
  uint layers = frame.gateInfo.y;
  uint firstLayer = kSpecGateTypeValue == kGateBins ? (jump > 0u ? jump - 1u : 0u) : 0u;
  uint lastLayer = kSpecGateTypeValue == kGateBins ? min(jump, layers - 1u) : 0u;
  float w = 0.0;
  for (uint k = firstLayer; k <= lastLayer; ++k) w += adjointOf(pixel, k) * gateJumpSize(jump, k);
  return w;
}

// The adjoint of one path vertex: of its position, its unit normal and the log of its area Jacobian.
struct VertexAdjoint {
  vec3 position;
  vec3 normal;
  float logJacobian;
};

VertexAdjoint noAdjoint() { return VertexAdjoint(vec3(0.0), vec3(0.0), 0.0); }

// Reverse of u = d / |d|: d's adjoint from u's.
vec3 normalizeAdjoint(vec3 u, float len, vec3 uBar) { return (uBar - u * dot(u, uBar)) / len; }

// A path vertex's adjoint onto the vertices of its triangle: the material point X = sum b_i V_i,
// the normal normalize(cross(V1 - V0, V2 - V0)) and the Jacobian |cross| / |cross at θ0|. A first hit
// kept on its camera ray (`rayForm`) moves along the ray: x' = (c . X') / (c . w) w
// (geometry_dual.glsl's rayHitRate, c the unnormalised normal), hence X's adjoint.
void scatterSurfaceAdjoint(uint triangle, vec2 uv, VertexAdjoint a, bool rayForm) {
  if (!differentiates(kAdjointVertices)) return;
  uvec4 ids = triangleVerts[triangle];
  if ((shapes[ids.w].flags & kShapeMoves) == 0u) return;
  GpuTriangle t = loadTriangle(triangle);
  vec3 e1 = t.p1.xyz - t.p0.xyz, e2 = t.p2.xyz - t.p0.xyz;
  vec3 c = cross(e1, e2);
  float c2 = dot(c, c);
  if (!(c2 > 0.0)) return;
  float w0 = 1.0 - uv.x - uv.y;
  vec3 xBar = a.position;
  if (rayForm) {
    vec3 x = w0 * t.p0.xyz + uv.x * t.p1.xyz + uv.y * t.p2.xyz;
    vec3 dir = normalize(x - cameraPosition());
    xBar = dot(xBar, dir) / dot(c, dir) * c;
  }
  float len = sqrt(c2);
  vec3 cBar = normalizeAdjoint(c / len, len, a.normal) + a.logJacobian * c / c2;
  vec3 e1Bar = cross(e2, cBar), e2Bar = cross(cBar, e1);
  scatterVertex(ids.x, w0 * xBar - e1Bar - e2Bar);
  scatterVertex(ids.y, uv.x * xBar + e1Bar);
  scatterVertex(ids.z, uv.y * xBar + e2Bar);
}

// One segment A -> B of a path and the factor it brings (THEORY.md §2-3):
//   F = f_A(wi, w) |n_A . w| |n_B . w| / |x_B - x_A|^2 J_B,
// w the unit direction A -> B, wi the one from A to its predecessor P. hasBsdf false: f = 1 (the
// sensor's importance); cosB false: a point light; jacobianB false: B does not move as a material
// point (a first hit on its camera ray, a point light).
struct Segment {
  vec3 p, a, b;
  vec3 nA, nB;
  uint materialA;
  bool hasBsdf, cosB, jacobianB;
};

// Adds valueWeight × ∇ log F and lengthWeight × ∇|x_B - x_A| to the adjoints of P, A and B (and
// F's material derivative to A's material).
void segmentAdjoint(Segment s, float valueWeight, float lengthWeight, inout VertexAdjoint P, inout VertexAdjoint A,
                    inout VertexAdjoint B) {
  vec3 d = s.b - s.a;
  float len = length(d);
  if (!(len > 0.0)) return;
  vec3 w = d / len;
  vec3 wBar = vec3(0.0);
  float lenBar = lengthWeight;
  bool geometry = differentiates(kAdjointVertices | kAdjointLights);
  if (valueWeight != 0.0) {
    float cA = dot(s.nA, w);
    if (cA != 0.0) {
      A.normal += valueWeight * w / cA;
      wBar += valueWeight * s.nA / cA;
    }
    if (s.cosB) {
      float cB = dot(s.nB, w);
      if (cB != 0.0) {
        B.normal += valueWeight * w / cB;
        wBar += valueWeight * s.nB / cB;
      }
    }
    lenBar -= 2.0 * valueWeight / len;
    if (s.jacobianB) B.logJacobian += valueWeight;
    if (s.hasBsdf && differentiates(kAdjointVertices | kAdjointLights | kAdjointMaterials)) {
      vec3 dp = s.p - s.a;
      float lp = length(dp);
      if (lp > 0.0) {
        vec3 wi = dp / lp;
        BsdfLogGradient g = bsdfLogGradient(s.materialA, s.nA, wi, w, geometry, differentiates(kAdjointMaterials));
        A.normal += valueWeight * g.n;
        wBar += valueWeight * g.wo;
        vec3 dpBar = normalizeAdjoint(wi, lp, valueWeight * g.wi);
        P.position += dpBar;
        A.position -= dpBar;
        scatterMaterial(s.materialA, valueWeight * g.material);
      }
    }
  }
  vec3 dBar = normalizeAdjoint(w, len, wBar) + lenBar * w;
  B.position += dBar;
  A.position -= dBar;
}
#endif
