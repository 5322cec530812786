// Ray-triangle and ray-box tests, the GLSL twin of src/scene/bvh.cpp (same constants, same order
// of operations). Include after lib/common.glsl.
//
// Triangle test: Möller–Trumbore, both faces, hit when tMin < t < tMax, barycentrics
// uv.x = weight of p1, uv.y = weight of p2. Two robustness rules:
//  - the determinant must exceed kDetRelative times the product of the infinity norms of both
//    edges and the direction (scale invariant: 1e-4 and 1e4 triangles alike); below that the ray
//    runs along the plane and the determinant is rounding noise;
//  - t must lie in the widened slab interval of the triangle's padded box (trianglePaddedBox).
//    Node boxes are unions of those padded boxes and the slab arithmetic is monotone, so the
//    traversal in lib/bvh.glsl can never cull a box holding an accepted hit, even when MT's t
//    is off for a grazing ray. The slab and padding arithmetic is `precise` (no FMA contraction)
//    so it rounds exactly like the host build that produced the node boxes.
// Directions must be finite and not all-zero; tiny components are handled by safeInverse().
#ifndef VKTG_INTERSECT_GLSL
#define VKTG_INTERSECT_GLSL

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

// Triangle test with a precomputed safeInverse(dir) (what the traversal uses). On a hit returns
// true with t and uv set.
bool intersectTrianglePrepared(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, vec3 invDir, float tMin, float tMax,
                               out float t, out vec2 uv) {
  t = 0.0;
  uv = vec2(0.0);
  vec3 e1 = p1 - p0;
  vec3 e2 = p2 - p0;
  vec3 pv = cross(dir, e2);
  float det = dot(e1, pv);
  if (!(abs(det) > kDetRelative * maxAbs3(e1) * maxAbs3(e2) * maxAbs3(dir))) return false;
  float invDet = 1.0 / det;
  vec3 s = origin - p0;
  float u = dot(s, pv) * invDet;
  if (!(u >= 0.0 && u <= 1.0)) return false;
  vec3 q = cross(s, e1);
  float v = dot(dir, q) * invDet;
  if (!(v >= 0.0 && u + v <= 1.0)) return false;
  float th = dot(e2, q) * invDet;
  if (!(th > tMin && th < tMax)) return false;
  vec3 lo, hi;
  trianglePaddedBox(p0, p1, p2, lo, hi);
  vec2 slab = slabInterval(lo, hi, origin, invDir);
  if (!(th >= slab.x && th <= slab.y)) return false;
  t = th;
  uv = vec2(u, v);
  return true;
}

// Standalone triangle test: on a hit in (tMin, tMax) sets tMax = t, uv, and returns true.
bool intersectTriangle(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, float tMin, inout float tMax, out vec2 uv) {
  float t;
  if (!intersectTrianglePrepared(p0, p1, p2, origin, dir, safeInverse(dir), tMin, tMax, t, uv)) return false;
  tMax = t;
  return true;
}
#endif
