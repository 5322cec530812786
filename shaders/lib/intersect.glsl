// Ray-triangle and ray-box tests, the GLSL twin of src/scene/bvh.cpp (same constants, same order
// of operations). Include after lib/common.glsl.
//
// Triangle test: watertight (Woop, Benthin, Wald 2013), both faces, hit when tMin < t < tMax,
// barycentrics uv.x = weight of p1, uv.y = weight of p2. The ray is the z axis of a sheared
// frame, scaled by the direction's largest component instead of divided by it, so the edge
// functions of an edge two triangles share are exact negatives (no ray slips between them) and
// no decision depends on a division: with `precise` on every operation they are the host's bits
// on any Vulkan device. Two robustness rules:
//  - |d . n| must exceed kDetRelative times the product of the infinity norms of both edges and
//    the direction (scale invariant: 1e-4 and 1e4 triangles alike); below that the ray runs
//    along the plane and the hit distance is rounding noise;
//  - t must lie in the widened slab interval of the triangle's padded box (trianglePaddedBox).
//    Node boxes are unions of those padded boxes and the slab arithmetic is monotone, so the
//    traversal in lib/bvh.glsl can never cull a box holding an accepted hit. The slab and
//    padding arithmetic is `precise` so it rounds exactly like the host build of the node boxes.
// The t reported for a hit is refined against the triangle's plane in double-float arithmetic
// (refinedHitDistance): about one ulp of the exact distance, docs/precision.md.
// Directions must be finite and not all-zero; tiny components are handled by safeInverse().
#ifndef VKTG_INTERSECT_GLSL
#define VKTG_INTERSECT_GLSL
#include "lib/double_float.glsl"

const float kTinyDirection = 1e-30;     // components below this are replaced before inverting
const float kSlabWiden = 1.0 / 8192.0;  // relative widening of slab intervals in t
const float kPadRelative = 1.0 / 4096.0;  // triangle box padding, fraction of its largest extent
const float kDetRelative = 1e-6;        // grazing limit of the determinant test

// Finite, non-zero inverse direction: a zero component becomes +-1e30 (sign kept), so the slab
// test never computes 0 * inf.
vec3 safeInverse(vec3 dir) {
  precise vec3 d = dir;
  for (int i = 0; i < 3; ++i) {
    if (!(abs(d[i]) >= kTinyDirection)) d[i] = (floatBitsToUint(d[i]) >> 31) != 0u ? -kTinyDirection : kTinyDirection;
  }
  precise vec3 inv = 1.0 / d;
  return inv;
}

float widenDown(float t) { precise float r = t * (t >= 0.0 ? 1.0 - kSlabWiden : 1.0 + kSlabWiden); return r; }
float widenUp(float t) { precise float r = t * (t >= 0.0 ? 1.0 + kSlabWiden : 1.0 - kSlabWiden); return r; }

// Widened (near, far) of the ray against box [lo, hi]; near > far on a miss. The face is picked by
// the sign of the inverse direction, so an inverted (empty) box is always missed.
vec2 slabInterval(vec3 lo, vec3 hi, vec3 origin, vec3 invDir) {
  bvec3 positive = greaterThanEqual(invDir, vec3(0.0));
  vec3 nearFace = mix(hi, lo, positive);
  vec3 farFace = mix(lo, hi, positive);
  precise vec3 tNear = (nearFace - origin) * invDir;
  precise vec3 tFar = (farFace - origin) * invDir;
  float n = max(max(tNear.x, tNear.y), tNear.z);
  float f = min(min(tFar.x, tFar.y), tFar.z);
  return vec2(widenDown(n), widenUp(f));
}

// The slab test of four boxes at once (the 4-wide BVH's children, structure of arrays): each
// component rounds exactly as slabInterval does for that box.
void slabIntervals4(vec4 loX, vec4 loY, vec4 loZ, vec4 hiX, vec4 hiY, vec4 hiZ, vec3 origin, vec3 invDir,
                    out vec4 near, out vec4 far) {
  precise vec4 nx = ((invDir.x >= 0.0 ? loX : hiX) - origin.x) * invDir.x;
  precise vec4 ny = ((invDir.y >= 0.0 ? loY : hiY) - origin.y) * invDir.y;
  precise vec4 nz = ((invDir.z >= 0.0 ? loZ : hiZ) - origin.z) * invDir.z;
  precise vec4 fx = ((invDir.x >= 0.0 ? hiX : loX) - origin.x) * invDir.x;
  precise vec4 fy = ((invDir.y >= 0.0 ? hiY : loY) - origin.y) * invDir.y;
  precise vec4 fz = ((invDir.z >= 0.0 ? hiZ : loZ) - origin.z) * invDir.z;
  vec4 n = max(max(nx, ny), nz);
  vec4 f = min(min(fx, fy), fz);
  precise vec4 down = n * mix(vec4(1.0 + kSlabWiden), vec4(1.0 - kSlabWiden), greaterThanEqual(n, vec4(0.0)));
  precise vec4 up = f * mix(vec4(1.0 - kSlabWiden), vec4(1.0 + kSlabWiden), greaterThanEqual(f, vec4(0.0)));
  near = down;
  far = up;
}

// Box of the triangle padded by kPadRelative of its largest extent (exactly as the host build).
void trianglePaddedBox(vec3 p0, vec3 p1, vec3 p2, out vec3 lo, out vec3 hi) {
  vec3 bl = min(min(p0, p1), p2);
  vec3 bh = max(max(p0, p1), p2);
  precise vec3 ext = bh - bl;
  precise float pad = kPadRelative * max(max(ext.x, ext.y), ext.z);
  precise vec3 l = bl - pad;
  precise vec3 h = bh + pad;
  lo = l;
  hi = h;
}

float maxAbs3(vec3 v) { vec3 a = abs(v); return max(max(a.x, a.y), a.z); }

// The direction's largest component (the first of equals) and the two that follow it.
uvec3 shearAxes(vec3 dir) {
  vec3 a = abs(dir);
  uint kz = a.x >= a.y ? (a.x >= a.z ? 0u : 2u) : (a.y >= a.z ? 1u : 2u);
  return uvec3((kz + 1u) % 3u, (kz + 2u) % 3u, kz);
}

// A vertex relative to the origin in the ray's sheared frame, scaled by dz.
vec2 shearVertex(vec3 p, vec3 dir, uvec3 k) {
  precise float x = dir[k.z] * p[k.x] - dir[k.x] * p[k.z];
  precise float y = dir[k.z] * p[k.y] - dir[k.y] * p[k.z];
  return vec2(x, y);
}

// Triangle test with a precomputed safeInverse(dir) and shearAxes(dir) (what the traversal uses).
// On a hit returns true with t (unrefined) and uv set.
bool intersectTrianglePrepared(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, vec3 invDir, uvec3 k, float tMin,
                               float tMax, out float t, out vec2 uv) {
  t = 0.0;
  uv = vec2(0.0);
  precise vec3 a = p0 - origin;
  precise vec3 b = p1 - origin;
  precise vec3 c = p2 - origin;
  vec2 as = shearVertex(a, dir, k), bs = shearVertex(b, dir, k), cs = shearVertex(c, dir, k);
  // Edge functions, each the (scaled) barycentric weight of the opposite vertex.
  precise float w0 = cs.x * bs.y - cs.y * bs.x;
  precise float w1 = as.x * cs.y - as.y * cs.x;
  precise float w2 = bs.x * as.y - bs.y * as.x;
  if ((w0 < 0.0 || w1 < 0.0 || w2 < 0.0) && (w0 > 0.0 || w1 > 0.0 || w2 > 0.0)) return false;
  // det = dz (d . n); negated comparison so a NaN misses too.
  precise float det = w0 + w1 + w2;
  precise vec3 e1 = p1 - p0;
  precise vec3 e2 = p2 - p0;
  float dz = dir[k.z];
  precise float limit = kDetRelative * maxAbs3(e1) * maxAbs3(e2) * (dz * dz);
  if (!(abs(det) > limit)) return false;
  precise float scaledT = w0 * a[k.z] + w1 * b[k.z] + w2 * c[k.z];
  precise float th = scaledT / (det * dz);
  if (!(th > tMin && th < tMax)) return false;
  vec3 lo, hi;
  trianglePaddedBox(p0, p1, p2, lo, hi);
  vec2 slab = slabInterval(lo, hi, origin, invDir);
  if (!(th >= slab.x && th <= slab.y)) return false;
  t = th;
  uv = vec2(w1, w2) / det;
  return true;
}

// The distance along the ray to the triangle's plane, (p0 - o) . n / (d . n) with n = e1 x e2, in
// double-float arithmetic (the twin of refinedHitDistance in src/scene/bvh.cpp). `t`: the test's
// distance, kept where the refinement cannot improve on it.
float refinedHitDistance(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, float t) {
  vec2 e1[3], e2[3], a[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = twoSum(p1[i], -p0[i]);
    e2[i] = twoSum(p2[i], -p0[i]);
    a[i] = twoSum(p0[i], -origin[i]);
  }
  vec2 n[3];
  for (int i = 0; i < 3; ++i) {
    int j = (i + 1) % 3, l = (i + 2) % 3;
    n[i] = dfAdd(dfMul(e1[j], e2[l]), dfNegate(dfMul(e1[l], e2[j])));
  }
  vec2 numerator = vec2(0.0), denominator = vec2(0.0);
  for (int i = 0; i < 3; ++i) {
    numerator = dfAdd(numerator, dfMul(a[i], n[i]));
    denominator = dfAdd(denominator, dfMul(vec2(dir[i], 0.0), n[i]));
  }
  if (!(abs(denominator.x) > 0.0)) return t;
  float refined = dfDivide(numerator, denominator);
  return isinf(refined) || isnan(refined) ? t : refined;
}

// Standalone triangle test: on a hit in (tMin, tMax) sets tMax = t (refined), uv, and returns true.
bool intersectTriangle(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, float tMin, inout float tMax, out vec2 uv) {
  float t;
  if (!intersectTrianglePrepared(p0, p1, p2, origin, dir, safeInverse(dir), shearAxes(dir), tMin, tMax, t, uv))
    return false;
  tMax = refinedHitDistance(p0, p1, p2, origin, dir, t);
  return true;
}
#endif
