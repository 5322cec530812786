#version 460
#extension GL_GOOGLE_include_directive : require
// Pass sample_edges (the visibility-boundary term; lib/edge.glsl has the mathematics): one edge
// sample per invocation. Picks a point y on a silhouette-capable edge (by length) and one of three
// strategies (kPrimary*, kToLight* probabilities; by blocks of samples, see edgeStrategy):
//   primary:   the segment from the camera (sensor) through y; behind a pinhole both sides of the
//              silhouette are taken (the ray just past the edge, and the edge's face at y), at a
//              point sensor only the unoccluded side (its first hits are material points); behind
//              a pinhole a crease the camera sees both faces of is taken on both sides too (each
//              face at y);
//   to light:  the segment from a light sample x_b (area or point light) through y, traced on to
//              x_a, which connects to the camera: a shadow boundary of direct light, complete here;
//   secondary: a uniform direction w at y, traced both ways to x_a (-w) and x_b (+w); x_a
//              connects to the camera, and the light side continues from x_b except x_b's own
//              emission (the to-light strategy's share: the change of variables from w to the
//              visible light point covers exactly those paths).
// In the last two the boundary segment is the path's second. The light side of primary and
// secondary samples continues from the hit at the end of the boundary segment through the
// ordinary shade and trace_shadow_rays passes, which close it with emission, standard or
// ellipsoidal NEE at any depth, so a narrow gate still lands every path in its support. Each
// sample owns two path slots (2i: the unoccluded side, 2i + 1: the occluded side of a primary
// pinhole sample, or the to-light path); each slot's boundary geometry goes to its EdgeRecord,
// from which accumulate_splats (forward lanes: the factor -v_n, +v_n on the occluded side) or
// scatter_edges (the adjoint) finish the slot once its light side is known.
// Reads: edges and their faces, scene BVH, camera. Writes: paths[2i, 2i+1], hits, ray queue 0,
// edge records, edge counters; the first step the strategies' queues. Dispatch: ceil(edge samples
// of the batch / kWorkgroupSize) for the first step (or for all strategies in one), then indirect
// over each strategy's queue (below); push.args: x first edge sample of the batch, w samples in
// the batch.
#include "lib/common.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/bvh.glsl"
#include "lib/nee.glsl"
#include "lib/edge.glsl"
#include "lib/camera.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform Push { PassPush push; };

// How far from the edge the traced rays pass, in ray epsilons. A boundary segment is the limit of
// the rays beside the edge as they close in on it, and whatever lies within the offset's reach of
// that limit is seen wrongly: a box 5 cm above a floor, under a light, casts the shadow of its
// bottom edge 0.6 mm beside where the ray past that edge meets the floor, and 8 ray epsilons
// (1 mm in that scene) jumped the shadow, so the silhouette counted the lit floor and the shadow's
// own boundary counted the same jump again (docs/theory.md 3.3, "Rays beside an edge"). So the
// offset is a small fraction of a ray epsilon, and the edge's own faces, which lie wholly on the
// other side of the boundary plane and so are never really hit from this side, are skipped by
// name (traceClosestPastFaces) rather than by distance. The sides that see the edge's own faces
// are not traced at all but taken at their limit (faceBesideEdge).
const float kEdgeOffsetEpsilons = 1.0 / 16.0;
// How far in front of the edge an occluder must be to hide it from the camera, in ray epsilons:
// rounding must not let the edge's own faces, which the line onto it meets at the edge, count.
const float kHiddenMarginEpsilons = 8.0;
const uint kRngDimEdgeWalk = 8u;  // + walk step: the camera side's numbers (stream kNoPixel)
// Strategy probabilities: shadows of direct light are usually the largest secondary share and the
// uniform direction rarely finds a small light, hence the split: 7, 9 and 4 blocks of a cycle of 20.
//
// The strategy goes by block of kEdgeStrategyBlock consecutive samples, the cycle rotated by a
// whole number of blocks drawn from the render's seed. For any one sample that offset makes its
// strategy's block uniform over the cycle, so each strategy has exactly its probability and the
// weights 1 / probability stay right; but invocations that run together now share one strategy. A
// CPU device runs every branch that any lane of its SIMD group takes (three strategies, five BVH
// traversals, per group when the choice was per sample), and a GPU warp diverges on the same.
//
// Each strategy runs as a pipeline of its own (kSpecEdgeStrategy) over the samples that are its
// own: a first step (kEdgeSortSamples) gives every sample of the batch its empty slots and queues
// it by strategy, then one dispatch per strategy runs over its queue (kCounterEdgeQueues). In one
// pipeline the three took an H100 1.7 times as long as apart, about as long as the primary strategy
// alone takes for every sample: a pipeline is compiled for its heaviest code, and the primary
// strategy's appears to limit how many invocations the GPU holds at once. On lavapipe this pass
// paid for its code even in invocations that left before reaching it: 140 ms where every
// invocation left after clearing its slots, against 20 ms with the rest compiled out (the same
// experiment costs connect_camera_boundary nothing; docs/benchmarks.md, "On a GPU: NVIDIA H100"
// and "What the 3× goal at 121 heights would take"), so each strategy's code sees only its own
// samples. Each sample takes the same path whichever way it is dispatched
// (VKTG_EDGE_DISPATCH=single: one pipeline for all strategies, over every sample).
const uint kEdgeStrategyBlock = 32u, kEdgeStrategyCycle = 20u;
const uint kPrimaryBlocks = 7u, kToLightBlocks = 9u;
const float kPrimaryProbability = float(kPrimaryBlocks) / float(kEdgeStrategyCycle);
const float kToLightProbability = float(kToLightBlocks) / float(kEdgeStrategyCycle);
const float kSecondaryProbability = 1.0 - kPrimaryProbability - kToLightProbability;

// The strategy of sample `sampleIndex`, and its place among that strategy's samples (counted from
// the first block of its cycle: a constant off, which the stratified sequence's shift absorbs).
uint edgeStrategy(uint sampleIndex, out uint place) {
  // The offset's stream: no edge sample has index 0xffffffff (a render holds fewer than 2^32).
  uint offset = hash4(uvec4(kNoPixel, 0xffffffffu, kRngDimCamera, viewSeed())).x % kEdgeStrategyCycle;
  uint block = sampleIndex / kEdgeStrategyBlock + offset;
  uint cycle = block / kEdgeStrategyCycle, inCycle = block % kEdgeStrategyCycle;
  // The strategy's blocks are [first, first + blocks) of the cycle.
  uint strategy = kEdgeStrategySecondary, first = kPrimaryBlocks + kToLightBlocks, blocks = kEdgeStrategyCycle - first;
  if (inCycle < kPrimaryBlocks) {
    strategy = kEdgeStrategyPrimary;
    first = 0u;
    blocks = kPrimaryBlocks;
  } else if (inCycle < kPrimaryBlocks + kToLightBlocks) {
    strategy = kEdgeStrategyToLight;
    first = kPrimaryBlocks;
    blocks = kToLightBlocks;
  }
  place = (cycle * blocks + inCycle - first) * kEdgeStrategyBlock + sampleIndex % kEdgeStrategyBlock;
  return strategy;
}

// x_a at depth 1 behind a pinhole stays on its camera ray (the interior pass's parametrisation).
bool endAOnCameraRay(uint depth) { return depth == 1u && kSpecCameraTypeValue == kCameraPerspective; }

// Per edge, its faces' triangles (z, w; ~0 for none), in the order of inward0 and inward1.
layout(std430, set = 0, binding = kBindingEdgeFaces) readonly buffer EdgeFacesBlock { uvec4 edgeFaces[]; };

// What the camera sees just beside edge `edge` at y (distance dA along w), on the side of the
// boundary plane that `side` points to, where the line onto y is unoccluded: in the limit of rays
// closing in on y from that side, the edge's own face on that side, at y. Taken as that limit
// rather than traced at an offset: a face seen nearly edge-on is narrower in the image than
// any offset, and a ray beside it would miss it and count what lies behind (a faceted sphere's
// creases next to its outline counted the floor beyond it: 29% too much at 20480 faces).
// A crease has one face on either side; on a silhouette's face side both lie there, and the one
// seen is the one whose plane the rays cross first, the smaller (d.w) / |d.side| for the faces'
// inward directions d. The point is taken kFaceInsetEpsilons into the face from y: at y itself a
// path would start on the edge, and where the edge rests on another surface (a box on a floor)
// within a ray epsilon of it, where rays leaving the point cannot tell that surface from their
// own start (a resting box's edge term went from +1.09 to +3.68).
const float kFaceInsetEpsilons = 1.0;

HitRecord faceBesideEdge(uint edge, GpuEdge e, vec3 y, vec3 w, float dA, vec3 side) {
  uvec2 faces = edgeFaces[edge].zw;
  vec3 d0 = e.inward0.xyz, d1 = e.inward1.xyz;
  bool first = true;
  if (faces.y != 0xffffffffu) {
    float s0 = dot(d0, side), s1 = dot(d1, side);
    if ((s0 > 0.0) != (s1 > 0.0)) first = s0 > 0.0;  // a crease
    else first = dot(d0, w) * abs(s1) < dot(d1, w) * abs(s0);
  }
  uint face = first ? faces.x : faces.y;
  vec3 p = y + kFaceInsetEpsilons * frame.sceneInfo.x * (first ? d0 : d1);
  // p's barycentrics in the face (clamped: a face narrower than the inset keeps its point inside).
  GpuTriangle tri = loadTriangle(face);
  vec3 e1 = tri.p1.xyz - tri.p0.xyz, e2 = tri.p2.xyz - tri.p0.xyz, q = p - tri.p0.xyz;
  float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), q1 = dot(q, e1), q2 = dot(q, e2);
  float det = d00 * d11 - d01 * d01;
  vec2 uv = clamp(vec2(d11 * q1 - d01 * q2, d00 * q2 - d01 * q1) / det, 0.0, 1.0);
  if (uv.x + uv.y > 1.0) uv /= uv.x + uv.y;
  return closestHitRecord(true, distance(y - dA * w, p), uv, face);
}

// The closest hit past the edge's own faces (traceClosest otherwise): from the side of the boundary
// plane away from them they are met only by rounding, however near the ray passes.
bool traceClosestPastFaces(uint edge, vec3 origin, vec3 dir, float tMin, out HitRecord hit) {
  uvec2 faces = edgeFaces[edge].zw;
  for (uint attempt = 0u; attempt < 3u; ++attempt) {
    if (!traceClosest(origin, dir, tMin, kInfinity, hit)) return false;
    uint triangle = floatBitsToUint(hit.tuvTriangle.w);
    if (triangle != faces.x && triangle != faces.y) return true;
    tMin = hit.tuvTriangle.x;
  }
  return false;
}

// Hands slot `slot` to shade: the path stands at `from` (vertex `depth`, reached over length
// `len`) and its next segment, the boundary segment or the ray beside it, ends at `hit`.
void startEdgePath(uint slot, vec3 from, vec3 before, uint fromTriangle, vec3 fromNormal, float len, vec3 dir,
                   HitRecord hit, float throughput, float ior, uint depth, uint pixel, uint sampleIndex, uint flags) {
  uint firstEllipsoid = max(frame.pathInfo.y, depth + 1u);
  PathState ps;
  ps.position = vec4(from, len);
  ps.direction = vec4(dir, 0.0);
  ps.normal = vec4(fromNormal, throughput);
  ps.misc = vec4(0.0, ior, viewBits(), 0.0);
  ps.ids = uvec4(pixel, sampleIndex, depth, flags | kPathFlagEdgeArrival | ((firstEllipsoid + 1u) << kPathEllipsoidShift));
  ps.previous = vec4(before, uintBitsToFloat(fromTriangle));
  paths[slot] = ps;
  hits[slot] = hit;
  uint queued = atomicAdd(counters[kCounterRays0], 1u);
  rayQueues[queued] = slot;
}

// The side of a primary boundary behind a pinhole that sees the edge's face (the side `side`
// points to), into slot `slot`. Its first hit stays on its camera ray, so it has no normal
// velocity of its own and the slot's factor is `factor` v_y.n_p alone.
void startFaceSide(uint slot, uint edge, GpuEdge e, float t, vec3 np, vec3 side, float factor, vec3 c, vec3 y, vec3 w,
                   float dA, float weight, uint pixel, uint sampleIndex) {
  HitRecord h = faceBesideEdge(edge, e, y, w, dA, side);
  EdgeRecord r = boundaryRecord(edge, t, np, 1.0, 1.0);
  r.normalScale.w = factor;
  r.ends.yz = vec2(0.0);
  edgeRecords[slot] = r;
  startEdgePath(slot, c, c, 0xffffffffu, cameraForward(), 0.0, w, h, weight, 1.0, 0u, pixel, sampleIndex, 0u);
}

void primarySample(uint i, uint sampleIndex, uint edge, GpuEdge e, float t, vec3 y, float pY, float offset) {
  vec3 c = cameraPosition();
  float dA = distance(y, c);
  vec3 w = (y - c) / dA;
  bool pinhole = kSpecCameraTypeValue == kCameraPerspective;
  vec3 np;
  float sinPhi;
  bool silhouette = silhouettePlane(e, w, np, sinPhi);
  // Behind a pinhole the first hit stays on its camera ray, so where the ray crosses from one face
  // of a crease to the other the integrand jumps by the difference of their radiance, and a moving
  // crease moves that jump across the image like a silhouette (THEORY.md 3.3, "Creases behind a
  // pinhole"). A point sensor's first hits are material points, in whose coordinates a crease does
  // not move.
  bool crease = !silhouette && pinhole && creasePlane(e, w, np, sinPhi);
  if (!silhouette && !crease) return;
  atomicAdd(counters[kCounterEdgeSilhouettes], 1u);
  uint pixel;
  float importance = cameraImportance(w, pixel);
  if (importance == 0.0) return;
  float eps = frame.sceneInfo.x;
  float weight = importance * sinPhi / (dA * dA * pY * kPrimaryProbability);
  if (crease) {
    // The line onto the crease meets its faces only at y: anything it hits before is in front.
    if (traceAny(c, w, eps, dA - kHiddenMarginEpsilons * eps)) return;
    atomicAdd(counters[kCounterEdgeConnected], 1u);
    // Both sides see a face: the one n_p points to gets -v_y.n_p, the other +v_y.n_p.
    startFaceSide(2u * i, edge, e, t, np, np, -1.0, c, y, w, dA, weight, pixel, sampleIndex);
    startFaceSide(2u * i + 1u, edge, e, t, np, -np, 1.0, c, y, w, dA, weight, pixel, sampleIndex);
    return;
  }
  vec3 wVisible = normalize(y + offset * np - c);
  HitRecord hb;
  bool hitB = traceClosestPastFaces(edge, c, wVisible, eps, hb);
  if (hitB && hb.tuvTriangle.x < dA - kHiddenMarginEpsilons * eps) return;  // something nearer hides the edge
  atomicAdd(counters[kCounterEdgeConnected], 1u);
  if (hitB) {
    uint tb = floatBitsToUint(hb.tuvTriangle.w);
    float dB = max(distance(surfacePoint(tb, hb.tuvTriangle.yz).position, y), 0.0);
    EdgeRecord r = boundaryRecord(edge, t, np, dA, dB);
    // Behind a pinhole x_b slides along the ray, within the plane: no normal velocity.
    if (!pinhole) recordEndB(r, tb, hb.tuvTriangle.yz, 0xffffffffu);
    edgeRecords[2u * i] = r;
    startEdgePath(2u * i, c, c, 0xffffffffu, cameraForward(), 0.0, wVisible, hb, weight, 1.0, 0u, pixel,
                  sampleIndex, 0u);
  }
  if (!pinhole) return;
  // The pixel's other side sees the edge's face: its radiance is what the silhouette uncovers
  // when it moves away from n_p.
  startFaceSide(2u * i + 1u, edge, e, t, np, -np, 1.0, c, y, w, dA, weight, pixel, sampleIndex);
}

// The camera's view of a surface point: importance times the geometry term of point -> camera
// (0 if hidden or outside the image), its pixel, and the distance and unit direction to the camera.
float cameraConnection(vec3 position, vec3 normal, out uint pixel, out vec3 wc, out float r) {
  vec3 c = cameraPosition();
  r = distance(c, position);
  pixel = kNoPixel;
  wc = vec3(0.0);
  if (!(r > 0.0)) return 0.0;
  wc = (c - position) / r;
  float importance = cameraImportance(-wc, pixel);
  if (importance == 0.0) return 0.0;
  float eps = frame.sceneInfo.x;
  if (r > 2.0 * eps && traceAny(position, wc, eps, r - eps)) return 0.0;
  return importance * abs(dot(normal, wc)) / (r * r);
}

// The refractive index of the medium a direction d leaves a surface point into: a dielectric's
// inside or outside by the side of its (outward) normal; past any other surface the medium the
// path was in, `current`.
float mediumToward(GpuMaterial m, vec3 normal, vec3 d, float current) {
  if (!sceneHasMaterial(kMaterialDielectric) || m.type != kMaterialDielectric) return current;
  return dot(normal, d) < 0.0 ? m.ior : 1.0;
}

// The camera side of a boundary segment that leaves x_a along w: a walk of c >= 1 segments back
// to the camera, so the boundary segment can sit at any depth of the path. At each vertex that
// sees the camera (f != 0 towards it) the walk connects with probability kConnectProbability
// (always at its last allowed vertex) or samples the BSDF away from it (reciprocal BSDFs: the walk
// runs against the light's direction); a vertex that cannot connect always continues, so a
// boundary the camera sees only via a bounce does not lose half its samples to hidden connections
// (unbiased: the choice depends only on the walk so far).
// Through a dielectric it reflects or refracts like any vertex. The walk samples f(toward, wo) where
// the path needs f(wo, toward), and refraction is not reciprocal: f(wo, toward) = (eta_wo /
// eta_toward)^2 f(toward, wo) (lib/bsdf.glsl), so a refraction multiplies the weight by that ratio.
// Each segment counts the optical length of the medium it runs in: at a dielectric the side a
// direction leaves to says which; past any other vertex the medium stays (as shade tracks it).
// Returns the camera side's weight including f at x_a (0 on failure), with the pixel, the camera
// side's optical length, c (x_a's depth) and the IOR of the medium the boundary segment runs in.
const float kConnectProbability = 0.5;

float cameraSide(SurfacePoint xa, vec3 w, uint sampleIndex, out uint pixel, out float len, out uint depth,
                 out float ior) {
  pixel = kNoPixel;
  len = 0.0;
  depth = 0u;
  ior = 1.0;
  // Segments the camera side may use: the boundary segment needs one, the rest of the path none.
  uint maxSegments = frame.gateInfo.w > 1u ? frame.gateInfo.w - 1u : 0u;
  vec3 position = xa.position, normal = xa.normal, toward = w;  // toward: away from the camera side
  GpuMaterial m = materials[shapes[xa.shape].material];
  // The boundary segment's medium: the glass's when it leaves a dielectric x_a inwards, else air.
  ior = mediumToward(m, normal, toward, 1.0);
  float medium = ior;  // of the walk's segments before the current vertex
  float weight = 1.0, comp = 0.0;
  for (uint c = 1u; c <= maxSegments; ++c) {
    Rng rng = rngCreate(kNoPixel, sampleIndex, kRngDimEdgeWalk + c, viewSeed());
    vec4 u = rngNext4(rng);
    bool last = c == maxSegments;
    vec3 wc;
    float r;
    uint connectedPixel;
    float connection = cameraConnection(position, normal, connectedPixel, wc, r);
    if (connection != 0.0) connection *= bsdfEval(m, normal, wc, toward);
    // The camera is in air: a connection through a dielectric leaves it outwards (one from inside is
    // occluded by the glass it is in, unless the mesh is open).
    if (connection != 0.0 && mediumToward(m, normal, wc, medium) != 1.0) connection = 0.0;
    float connectProbability = connection == 0.0 ? 0.0 : (last ? 1.0 : kConnectProbability);
    if (u.w < connectProbability) {
      addLength(len, comp, r);
      depth = c;
      pixel = connectedPixel;
      return weight * connection / connectProbability;
    }
    if (last) return 0.0;
    BsdfSample bs;
    if (!bsdfSample(m, normal, toward, u.xyz, bs)) return 0.0;
    weight *= bs.weight / (1.0 - connectProbability);
    if (bs.transmitted) {
      float behind = mediumToward(m, normal, bs.wo, medium);
      weight *= (behind / medium) * (behind / medium);
      medium = behind;
    }
    HitRecord hit;
    if (!traceClosest(position, bs.wo, frame.sceneInfo.x, kInfinity, hit)) return 0.0;
    SurfacePoint next = surfacePoint(floatBitsToUint(hit.tuvTriangle.w), hit.tuvTriangle.yz);
    addLength(len, comp, distance(position, next.position) * medium);
    if (len > gateSupportNumbers().y) return 0.0;  // the path is already past the gate
    toward = -bs.wo;
    position = next.position;
    normal = next.normal;
    m = materials[shapes[next.shape].material];
  }
  return 0.0;
}

// The end x_a of a boundary segment that leaves it along w, and its camera side: the first hit
// from yv (beside the edge) along -w, and cameraSide's walk from it.
struct CameraEnd {
  SurfacePoint point;
  uint triangle;
  vec2 uv;
  float weight;   // cameraSide's weight (> 0 when found)
  uint pixel, depth;
  float len, ior;
};

bool findCameraEnd(uint edge, vec3 yv, vec3 w, uint sampleIndex, out CameraEnd a) {
  a.weight = 0.0;
  HitRecord ha;
  if (!traceClosestPastFaces(edge, yv, -w, 0.0, ha)) return false;
  a.triangle = floatBitsToUint(ha.tuvTriangle.w);
  a.uv = ha.tuvTriangle.yz;
  a.point = surfacePoint(a.triangle, a.uv);
  a.weight = cameraSide(a.point, w, sampleIndex, a.pixel, a.len, a.depth, a.ior);
  if (a.weight == 0.0) return false;
  atomicAdd(counters[kCounterEdgeConnected], 1u);
  return true;
}

void secondarySample(uint i, uint sampleIndex, uint edge, GpuEdge e, float t, vec3 y, float pY, float offset, vec2 uDir) {
  vec3 w = sampleUniformSphere(uDir);
  vec3 np;
  float sinPhi;
  if (!silhouettePlane(e, w, np, sinPhi)) return;
  atomicAdd(counters[kCounterEdgeSilhouettes], 1u);
  vec3 yv = y + offset * np;
  HitRecord hb;
  if (!traceClosestPastFaces(edge, yv, w, 0.0, hb)) return;
  CameraEnd a;
  if (!findCameraEnd(edge, yv, w, sampleIndex, a)) return;
  uint tb = floatBitsToUint(hb.tuvTriangle.w);
  // 1 / p_w = 4 pi for the uniform direction.
  float weight = a.weight * sinPhi * 4.0 * kPi / (pY * kSecondaryProbability);
  float dA = distance(y, a.point.position), dB = distance(surfacePoint(tb, hb.tuvTriangle.yz).position, y);
  EdgeRecord r = boundaryRecord(edge, t, np, dA, dB);
  recordEndA(r, a.triangle, a.uv, endAOnCameraRay(a.depth));
  recordEndB(r, tb, hb.tuvTriangle.yz, 0xffffffffu);
  edgeRecords[2u * i] = r;
  startEdgePath(2u * i, a.point.position, a.point.position, a.triangle, a.point.normal, a.len, w, hb, weight, a.ior,
                a.depth, a.pixel, sampleIndex, kPathFlagNoArrivalEmission);
}

// Direct light through the boundary: x_b a light sample, the segment x_b -> y -> x_a. Changing
// variables from the direction at y to the light point (dw = |cos_b| dA_b / |x_b - y|^2, x_b the
// first thing y sees that way) turns 1 / p_w into |cos_b| / (|x_b - y|^2 p_A); a point light is a
// fixed end (1 / |x_b - y|^2, its selection probability in place of p_A).
void toLightSample(uint i, uint sampleIndex, uint edge, GpuEdge e, float t, vec3 y, float pY, float offset, vec3 uLight) {
  LightSample ls;
  if (!sampleLight(uLight, ls)) return;
  float dB = distance(ls.position, y);
  if (!(dB > 0.0)) return;
  vec3 w = (ls.position - y) / dB;  // from y towards the light: +w is the x_b side
  vec3 np;
  float sinPhi;
  if (!silhouettePlane(e, w, np, sinPhi)) return;
  atomicAdd(counters[kCounterEdgeSilhouettes], 1u);
  float cosB = 1.0;
  if (!ls.isPoint) {
    cosB = dot(ls.normal, -w);
    if (cosB <= 0.0) return;  // area lights emit from their front face
  }
  float eps = frame.sceneInfo.x;
  vec3 yv = y + offset * np;
  vec3 toLight = ls.position - yv;
  float lightDistance = length(toLight);
  if (lightDistance > 2.0 * eps && traceAny(yv, toLight / lightDistance, eps, lightDistance - eps)) return;
  CameraEnd a;
  if (!findCameraEnd(edge, yv, w, sampleIndex, a)) return;
  float dA = distance(y, a.point.position);
  float value = a.weight * ls.emission * sinPhi * cosB / (dB * dB * ls.pdf * pY * kToLightProbability);
  float len = a.len, comp = 0.0;
  addLength(len, comp, distance(a.point.position, ls.position) * a.ior);
  uint slot = 2u * i + 1u;
  EdgeRecord r = boundaryRecord(edge, t, np, dA, dB);
  recordEndA(r, a.triangle, a.uv, endAOnCameraRay(a.depth));
  if (ls.isPoint) recordEndB(r, 0xffffffffu, vec2(0.0), ls.index);
  else recordEndB(r, ls.triangle, ls.barycentrics, 0xffffffffu);
  edgeRecords[slot] = r;
  paths[slot].ids.x = a.pixel;
  addContribution(slot, value, len);
}

// Strategy s's queue of the batch's samples: ray queues 1 and 2 (the shadow queue), unused until
// the light sides' first bounce, hold the three (a batch holds half as many samples as paths).
uint edgeQueueEntry(uint strategy, uint index) { return frame.pathInfo.w + strategy * (frame.pathInfo.w / 2u) + index; }

// The sample's empty slots (pixel kNoPixel, an empty record), which its strategy may fill.
void clearSlots(uint i, uint sampleIndex) {
  for (uint side = 0u; side < 2u; ++side) {
    paths[2u * i + side].ids = uvec4(kNoPixel, sampleIndex, 0u, 0u);
    paths[2u * i + side].misc.z = viewBits();
    edgeRecords[2u * i + side] = EdgeRecord(vec4(0.0), vec4(0.0), uvec4(0xffffffffu), uvec4(0xffffffffu));
  }
}

void main() {
  // The sample: the batch's i-th, or in a strategy's pipeline the i-th of its queue.
  uint i = gl_GlobalInvocationID.x;
  if (kSpecEdgeStrategyValue < kEdgeStrategyCount) {
    if (i >= counters[kCounterEdgeQueues + kSpecEdgeStrategyValue]) return;
    i = rayQueues[edgeQueueEntry(kSpecEdgeStrategyValue, i)];
  } else if (i >= push.args.w) {
    return;
  }
  // Random numbers are keyed by the sample's index within its view.
  setViewOfSample(push.args.x + i);
  uint sampleIndex = viewSample(push.args.x + i);
  uint place;
  uint sampled = edgeStrategy(sampleIndex, place);
  // In a strategy's pipeline a constant: the other strategies' code is left out.
  uint strategy = kSpecEdgeStrategyValue < kEdgeStrategyCount ? kSpecEdgeStrategyValue : sampled;
  if (kSpecEdgeStrategyValue == kEdgeSortSamples) {
    clearSlots(i, sampleIndex);
    if (frame.edgeInfo.x == 0u) return;
    uint entry = atomicAdd(counters[kCounterEdgeQueues + strategy], 1u);
    rayQueues[edgeQueueEntry(strategy, entry)] = i;
    return;
  }
  if (kSpecEdgeStrategyValue == kEdgeStrategyCount) clearSlots(i, sampleIndex);
  if (frame.edgeInfo.x == 0u) return;
  Rng rng = rngCreate(kNoPixel, sampleIndex, kRngDimCamera, viewSeed());
  uvec4 bits = rngNextBits4(rng);
  // Stratified (docs/theory.md 3.7): the edge and the point along it from one number of the
  // strategy's own sequence, so a strategy's samples spread evenly over the length all edges
  // share by their selection weights. The point is where that number falls within the edge's
  // interval of the 32-bit numbers, turned by one random amount for the whole render: the turn
  // makes t uniform given the edge even where the interval is short (an edge among millions holds
  // about a thousand numbers), and keeps the spacing of the samples on an edge.
  bool stratified = kSpecStratifiedBoundaryValue != 0u;
  uint uEdge = stratified ? stratifiedBits(place, strategy, viewSeed()) : bits.x;
  uint edge = selectEdge(uEdge);
  GpuEdge e = edges[edge];
  float t = bitsToUnit(bits.y);
  if (stratified) {
    float turn = bitsToUnit(renderBits(kEdgeStrategyCount + strategy, viewSeed()));
    t = fract(placeInEdgeInterval(uEdge, edge) + turn);
  }
  vec3 y = mix(e.p0.xyz, e.p1.xyz, t);
  float pY = e.inward1.w / distance(e.p0.xyz, e.p1.xyz);
  float offset = kEdgeOffsetEpsilons * frame.sceneInfo.x;
  vec4 u2 = rngNext4(rng);
  if (strategy == kEdgeStrategyPrimary) primarySample(i, sampleIndex, edge, e, t, y, pY, offset);
  else if (strategy == kEdgeStrategyToLight) toLightSample(i, sampleIndex, edge, e, t, y, pY, offset, u2.xyz);
  else secondarySample(i, sampleIndex, edge, e, t, y, pY, offset, u2.xy);
}
