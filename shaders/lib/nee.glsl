// Next-event estimation from a path vertex: standard (connect to a light sample, MIS with BSDF
// sampling) and ellipsoidal (THEORY.md §4: draw a total length s from the gate, a light point y,
// and a new vertex on the ellipsoid with foci x and y, so the path lands exactly at length s).
// Both queue shadow rays; trace_shadow_rays adds their value if every segment is unoccluded.
#ifndef VKTG_NEE_GLSL
#define VKTG_NEE_GLSL
#include "lib/bsdf.glsl"
#include "lib/ellipsoid.glsl"
#include "lib/lights.glsl"
#include "lib/path.glsl"

// The vertex NEE starts from. At the point sensor (isSensor) the "BSDF" is the sensor's
// importance: 1 per unit projected solid angle on the side of `normal` (irradiance).
struct NeeVertex {
  vec3 position;
  vec3 normal;
  vec3 wi;
  GpuMaterial material;
  bool isSensor;
  float throughput;
  float len;
  // For the MIS weight of --nee mis: the vertex before this one, the path length there, the
  // solid-angle pdf with which this vertex was reached from it, and this vertex's triangle.
  vec3 previousPosition;
  float previousLen;
  float arrivalPdf;
  uint triangle;
  // For the derivative lanes: the path, the material point of this vertex, the material, and
  // whether it is the first hit (kept on its camera ray, arrivalDir).
  uint path;
  vec2 uv;
  uint materialIndex;
  bool rayForm;
  vec3 arrivalDir;
  // The first vertex of this path that can start an ellipsoidal connection (path.glsl's
  // pathFirstEllipsoidVertex): which estimator covers which path lengths, below.
  uint firstEllipsoidVertex;
  uint depth;  // this vertex's index on the path (0: the sensor); neeAtVertex sets it
};

#ifdef VKTG_ADJOINT
#include "lib/tape.glsl"

// What the adjoint's trace_shadow_rays needs to know of a queued connection's vertices beyond its
// first: the ellipsoidal vertex (if any) and the light sample.
void recordConnection(uint slot, uint middleTriangle, vec2 middleUv, LightSample ls) {
  if (slot == 0xffffffffu) return;
  shadowAdjoint[slot] = ShadowAdjoint(uvec4(middleTriangle, floatBitsToUint(middleUv), 0u),
                                      uvec4(ls.index, floatBitsToUint(ls.barycentrics), 0u));
}
#endif

#ifdef VKTG_DERIVATIVE
#include "lib/path_derivative.glsl"

VertexDual neeVertexDual(NeeVertex v, uint lane) {
  if (v.isSensor) {
    VertexDual s;
    s.position = dual3(v.position);
    s.normal = dual3(v.normal);
    s.jacobian = dual(1.0);
    return s;
  }
  return v.rayForm ? rayVertexDual(v.triangle, v.uv, v.arrivalDir, lane) : surfaceVertexDual(v.triangle, v.uv, lane);
}

// f at the NEE vertex toward `wo` for one lane (the sensor's importance is constant).
Dual neeVertexBsdfDual(NeeVertex v, VertexDual x, PathDerivative pd, Dual3 wo, uint lane) {
  if (v.isSensor) return dual(1.0);
  Dual3 previous = dual3(v.previousPosition, pd.previousLength.xyz);
  Dual3 wi = dualSegment(x.position, previous).dir;
  return bsdfOfMaterialDual(v.materialIndex, x.normal, wi, wo, lane);
}

// d(log) of the light's side of a connection ending at y over segment `seg` (geometry at y,
// Jacobian, emission).
float lightEndDLog(LightSample ls, LightDual y, DualSegment seg) {
  float d = dLogOf(y.emission) - 2.0 * dLogOf(seg.len);
  if (!ls.isPoint) d += dLogOf(dAbs(dDot(y.normal, seg.dir))) + dLogOf(y.jacobian);
  return d;
}

void standardNeeDerivatives(uint slot, NeeVertex v, LightSample ls, float value) {
  if (slot == 0xffffffffu) return;
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    PathDerivative pd = pathDerivs[v.path * kSpecLanesValue + lane];
    VertexDual x = neeVertexDual(v, lane);
    LightDual y = lightDual(ls, lane);
    DualSegment seg = dualSegment(x.position, y.position);
    Dual f = neeVertexBsdfDual(v, x, pd, seg.dir, lane);
    float dLog = pd.positionThroughput.w / v.throughput + dLogOf(f) + dLogOf(dAbsCos(x.normal, seg.dir)) +
                 lightEndDLog(ls, y, seg);
    storeShadowDerivative(slot, lane, value * dLog, pd.previousLength.w + seg.len.d);
  }
}

void ellipsoidalNeeDerivatives(uint slot, NeeVertex v, LightSample ls, EllipsoidSample es, uint shapeK, float value) {
  if (slot == 0xffffffffu) return;
  uint materialK = shapes[shapeK].material;
  for (uint lane = 0u; lane < kSpecLanesValue; ++lane) {
    PathDerivative pd = pathDerivs[v.path * kSpecLanesValue + lane];
    VertexDual x = neeVertexDual(v, lane);
    VertexDual e = surfaceVertexDual(es.triangle, es.barycentrics, lane);
    LightDual y = lightDual(ls, lane);
    DualSegment s1 = dualSegment(x.position, e.position);
    DualSegment s2 = dualSegment(e.position, y.position);
    Dual f1 = neeVertexBsdfDual(v, x, pd, s1.dir, lane);
    Dual f2 = bsdfOfMaterialDual(materialK, e.normal, dNeg(s1.dir), s2.dir, lane);
    float dLog = pd.positionThroughput.w / v.throughput + dLogOf(f1) + dLogOf(dAbsCos(x.normal, s1.dir)) +
                 dLogOf(dAbsCos(e.normal, s1.dir)) - 2.0 * dLogOf(s1.len) + dLogOf(e.jacobian) + dLogOf(f2) +
                 dLogOf(dAbsCos(e.normal, s2.dir)) + lightEndDLog(ls, y, s2);
    storeShadowDerivative(slot, lane, value * dLog, pd.previousLength.w + s1.len.d + s2.len.d);
  }
}
#endif

float vertexEval(NeeVertex v, vec3 wo) {
  return v.isSensor ? (dot(v.normal, wo) > 0.0 ? 1.0 : 0.0) : bsdfEval(v.material, v.normal, v.wi, wo);
}

float vertexPdf(NeeVertex v, vec3 wo) {
  return v.isSensor ? max(dot(v.normal, wo), 0.0) * kInvPi : bsdfPdf(v.material, v.normal, v.wi, wo);
}

// --nee mis, for a path x_{n-2} -> x_{n-1} -> y of total length s: the area density of x_{n-1}
// under BSDF sampling from x_{n-2} (standard NEE's way) and under the ellipsoidal connection
// from x_{n-2} (gate density times the conic density). The light's density is common to both.
float areaPdfBsdf(float pdfSolidAngle, vec3 from, vec3 to, vec3 normalAtTo) {
  vec3 d = to - from;
  float dist2 = dot(d, d);
  return pdfSolidAngle * abs(dot(normalAtTo, d)) / (dist2 * sqrt(dist2));
}

float areaPdfEllipsoidal(vec3 from, float lenAtFrom, vec3 light, float totalLen, uint triangle, vec3 position) {
  return gateSamplePdf(totalLen) * ellipsoidConnectionDensity(from, light, totalLen - lenAtFrom, triangle, position);
}

void standardNee(uint path, NeeVertex v, uint depth, vec3 u) {
  LightSample ls;
  if (!sampleLight(u, ls)) return;
  vec3 d = ls.position - v.position;
  float dist2 = dot(d, d);
  if (!(dist2 > 0.0)) return;
  float dist = sqrt(dist2);
  vec3 wo = d / dist;
  float f = vertexEval(v, wo);
  if (f == 0.0) return;
  float cosX = abs(dot(v.normal, wo));
  float len = v.len, comp = 0.0;
  addLength(len, comp, dist);
  if (!gateReaches(len)) return;
  // Paths an ellipsoidal connection can also make are weighted against it (and emitter hits do
  // not count for them); shorter ones are weighted against BSDF sampling of the emitter.
  bool againstEllipsoid = kSpecNeeModeValue == kNeeMis && depth >= v.firstEllipsoidVertex + 1u;
  float value;
  if (ls.isPoint) {
    value = v.throughput * f * cosX * ls.emission / (dist2 * ls.pdf);
  } else {
    float cosY = dot(ls.normal, -wo);
    if (cosY <= 0.0) return;
    float pdfLight = ls.pdf * dist2 / cosY;  // solid angle at x
    float mis = againstEllipsoid ? 1.0 : powerHeuristic(pdfLight, vertexPdf(v, wo));
    value = v.throughput * f * cosX * ls.emission * cosY / (dist2 * ls.pdf) * mis;
  }
  if (againstEllipsoid && value != 0.0) {
    float pBsdf = areaPdfBsdf(v.arrivalPdf, v.previousPosition, v.position, v.normal);
    float pEll = areaPdfEllipsoidal(v.previousPosition, v.previousLen, ls.position, len, v.triangle, v.position);
    value *= powerHeuristic(pBsdf, pEll);
  }
  uint slot = queueShadowRay(path, v.depth, kConnectionStandard, v.position, ls.position, vec3(0.0), 1u, value, len,
                             kNoJump);
#ifdef VKTG_DERIVATIVE
  standardNeeDerivatives(slot, v, ls, value);
#endif
#ifdef VKTG_ADJOINT
  recordConnection(slot, 0xffffffffu, vec2(0.0), ls);
#endif
}

// One ellipsoidal connection of total length s (1/p(s) = invPdfS), scaled by `share` (1/2 for
// each member of an antithetic pair), into connection slot `kind`; `jump` tags
// path-length-boundary connections.
void ellipsoidalConnection(uint path, NeeVertex v, float s, float invPdfS, float share, LightSample ls, vec4 uEllipsoid,
                           uint jump, uint kind);

void ellipsoidalNee(uint path, NeeVertex v, vec2 uGate, vec3 uLight, vec4 uEllipsoid) {
  float s;
  float invPdfS = gateSampleLength(uGate, s);
  LightSample ls;
  if (!sampleLight(uLight, ls)) return;
  if (kSpecAntitheticValue != 0u && kSpecGateTypeValue == kGateGaussian) {
    // Antithetic pair (THEORY.md §5): s and its mirror 2 mu - s share every other random number;
    // the symmetric gate gives both the same density, and W'(s) + W'(2 mu - s) = 0 cancels the
    // large derivative terms of a near-delta gate between the pair.
    float mirror = 2.0 * gateNumbers().x - s;
    if (invPdfS > 0.0) ellipsoidalConnection(path, v, s, invPdfS, 0.5, ls, uEllipsoid, kNoJump, kConnectionEllipsoidal);
    if (invPdfS > 0.0)
      ellipsoidalConnection(path, v, mirror, invPdfS, 0.5, ls, uEllipsoid, kNoJump, kConnectionEllipsoidal + 1u);
    return;
  }
  if (invPdfS > 0.0) ellipsoidalConnection(path, v, s, invPdfS, 1.0, ls, uEllipsoid, kNoJump, kConnectionEllipsoidal);
}

// Path-length boundary (THEORY.md §3): paths placed exactly on L = s_j by ellipsoidal
// connections from `v` to a light sample, for the jumps gateBoundaryJumps picks beyond the
// straight-line reach v.len + |v - light|. trace_shadow_rays_d multiplies by ΔW(s_j) dL/dθ.
void pathLengthBoundaryConnection(uint path, NeeVertex v, float uJump, vec3 uLight, vec4 uEllipsoid) {
  LightSample ls;
  if (!sampleLight(uLight, ls)) return;
  uint first;
  float weight;
  uint n = gateBoundaryJumps(v.len + distance(v.position, ls.position), uJump, first, weight);
  for (uint j = first; j < first + n; ++j)
    ellipsoidalConnection(path, v, gateJumpLocation(j), weight, 1.0, ls, uEllipsoid, j, kConnectionBoundary + j - first);
}

void ellipsoidalConnection(uint path, NeeVertex v, float s, float invPdfS, float share, LightSample ls, vec4 uEllipsoid,
                           uint jump, uint kind) {
  float sPrime = s - v.len;
  // The shell must be longer than the straight line x -> y; otherwise no path of length s exists.
  if (!(sPrime > distance(v.position, ls.position))) return;
  atomicAdd(counters[kCounterEllipsoidQueries], 1u);
  EllipsoidSample es;
  if (!sampleEllipsoidConnection(v.position, ls.position, sPrime, uEllipsoid, es)) {
    atomicAdd(counters[kCounterEllipsoidEmpty], 1u);
    return;
  }
  SurfacePoint xk = surfacePoint(es.triangle, es.barycentrics);
  vec3 d1 = xk.position - v.position;
  vec3 d2 = ls.position - xk.position;
  float len1 = length(d1), len2 = length(d2);
  if (!(len1 > 0.0) || !(len2 > 0.0)) return;
  vec3 w1 = d1 / len1, w2 = d2 / len2;
  float f1 = vertexEval(v, w1);
  if (f1 == 0.0) return;
  GpuMaterial mk = materials[shapes[xk.shape].material];
  float f2 = bsdfEval(mk, xk.normal, -w1, w2);
  if (f2 == 0.0) return;
  float g1 = abs(dot(v.normal, w1)) * abs(dot(xk.normal, w1)) / (len1 * len1);
  float g2 = abs(dot(xk.normal, w2)) / (len2 * len2);
  if (!ls.isPoint) {
    float cosY = dot(ls.normal, -w2);
    if (cosY <= 0.0) return;
    g2 *= cosY;
  }
  float value = share * v.throughput * f1 * g1 * f2 * g2 * ls.emission * es.weight * invPdfS / ls.pdf;
  if (kSpecNeeModeValue == kNeeMis && jump == kNoJump) {
    float pBsdf = vertexPdf(v, w1) * abs(dot(xk.normal, w1)) / (len1 * len1);
    float pEll = 1.0 / (invPdfS * es.weight);
    value *= powerHeuristic(pEll, pBsdf);
  }
  uint slot = queueShadowRay(path, v.depth, kind, v.position, xk.position, ls.position, 2u, value, s, jump);
#ifdef VKTG_DERIVATIVE
  ellipsoidalNeeDerivatives(slot, v, ls, es, xk.shape, value);
#endif
#ifdef VKTG_ADJOINT
  recordConnection(slot, es.triangle, es.barycentrics, ls);
#endif
}

// Which estimator covers which paths (e, the first vertex that can start an ellipsoidal
// connection: 0 at a point sensor, 1 behind a pinhole, the vertex after the boundary segment on an
// edge pass's paths): in ellipsoidal mode, paths
// with at most e + 1 segments use standard NEE (and emitter hits), longer ones ellipsoidal NEE.
// In mis mode both run wherever they can, and the weights above split the paths between them.
// A connection from vertex `depth` closes a path of depth + 1 (standard) or depth + 2 (ellipsoidal)
// segments; paths have at most frame.gateInfo.w segments (max depth).
bool standardNeeAt(uint depth, uint e) {
  return (kSpecNeeModeValue != kNeeEllipsoidal || depth <= e) && depth + 1u <= frame.gateInfo.w;
}
bool ellipsoidalNeeAt(uint depth, uint e) {
  return kSpecNeeModeValue != kNeeStandard && depth >= e && depth + 2u <= frame.gateInfo.w;
}
// An emitter hit at vertex `depth` closes a path of `depth` segments.
bool emitterHitCounts(uint depth, uint e) { return kSpecNeeModeValue == kNeeStandard || depth <= e + 1u; }

void neeAtVertex(uint path, NeeVertex v, uint depth, uint globalPixel, uint sampleIndex) {
  uint seed = viewSeed(), pixel = viewPixel(globalPixel);  // random numbers keyed within the view
  v.depth = depth;
  if (kSpecTermValue != kTermInterior && depth >= v.firstEllipsoidVertex && depth + 2u <= frame.gateInfo.w) {
    // Every path an ellipsoidal connection can make, placed on a jump instead of sampled from W.
    // The random numbers are those of the interior term's connections from this vertex, so the
    // pass running both terms computes exactly what the two separate passes do.
    Rng rg = rngForBounce(pixel, sampleIndex, depth, kRngSlotGate, seed);
    Rng rl = rngForBounce(pixel, sampleIndex, depth, kRngSlotEllipsoidLight, seed);
    Rng re = rngForBounce(pixel, sampleIndex, depth, kRngSlotEllipsoid, seed);
    pathLengthBoundaryConnection(path, v, rngNext4(rg).x, rngNext4(rl).xyz, rngNext4(re));
  }
  if (kSpecTermValue == kTermPathLength) return;
  if (standardNeeAt(depth, v.firstEllipsoidVertex)) {
    Rng r = rngForBounce(pixel, sampleIndex, depth, kRngSlotLight, seed);
    standardNee(path, v, depth, rngNext4(r).xyz);
  }
  if (ellipsoidalNeeAt(depth, v.firstEllipsoidVertex)) {
    Rng rg = rngForBounce(pixel, sampleIndex, depth, kRngSlotGate, seed);
    Rng rl = rngForBounce(pixel, sampleIndex, depth, kRngSlotEllipsoidLight, seed);
    Rng re = rngForBounce(pixel, sampleIndex, depth, kRngSlotEllipsoid, seed);
    ellipsoidalNee(path, v, rngNext4(rg).xy, rngNext4(rl).xyz, rngNext4(re));
  }
}
#endif
