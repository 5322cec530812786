// BVH traversal over the scene bound in lib/bindings.glsl (the GLSL twin of traceClosest /
// traceAny in src/scene/bvh.cpp; node layout: GpuBvhNode in include/vktg/gpu/shared.h).
// Include after lib/common.glsl and lib/bindings.glsl.
//
// Stack: kBvhStackSize entries (must equal vktg::kBvhStackSize in include/vktg/bvh.h; a unit test
// checks). The host builder keeps every leaf at depth <= 64 (root = 0) by switching from SAH to
// median splits when needed, and near-first traversal holds at most one entry per level above
// the current node, so the stack cannot overflow for any BVH buildBvh produces. A deeper foreign
// tree would end the traversal with what was found so far (no out-of-bounds write, no hang).
//
// Closest hit: smallest t, ties broken by the smaller triangle index, so the result does not
// depend on the visiting order and equals a brute-force loop over all triangles. The winner's t is
// then refined against its plane (lib/intersect.glsl).
#ifndef VKTG_BVH_GLSL
#define VKTG_BVH_GLSL
#include "lib/intersect.glsl"

const uint kBvhStackSize = 64u;

// The leaf's triangles first .. first + count - 1 against the closest hit so far (found, tBest,
// uvHit, triHit). Each is tested against the full window: a hit at exactly tBest with a smaller
// index still wins. Returns true at the first accepted hit when anyHit (the traversal stops).
bool bvhTestLeaf(uint first, uint count, vec3 origin, vec3 dir, vec3 invDir, uvec3 axes, float tMin, float tMax,
                 bool anyHit, inout bool found, inout float tBest, inout vec2 uvHit, inout uint triHit) {
  for (uint i = first; i < first + count; ++i) {
    GpuTriangle tri = loadTriangle(i);
    float t;
    vec2 uv;
    if (!intersectTrianglePrepared(tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, origin, dir, invDir, axes, tMin, tMax, t, uv))
      continue;
    if (!found || t < tBest || (t == tBest && i < triHit)) {
      found = true;
      tBest = t;
      uvHit = uv;
      triHit = i;
      if (anyHit) return true;
    }
  }
  return false;
}

// The end of a traversal: the closest hit's distance refined against its triangle's plane, -1 for
// a miss. Returns `found`.
bool bvhFinishHit(bool found, bool anyHit, vec3 origin, vec3 dir, float tBest, uint triHit, out float tHit) {
  tHit = found ? tBest : -1.0;
  if (found && !anyHit) {
    GpuTriangle tri = loadTriangle(triHit);
    tHit = refinedHitDistance(tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, origin, dir, tHit);
  }
  return found;
}

// The 4-wide tree (kSpecWideBvh, GpuWideBvhNode): a node's hit children are ordered by entry
// distance, the nearest visited next and the others pushed, leaves as stack entries of their own
// (their child codes). The same boxes, slab arithmetic and tie rule as the binary traversal, so
// the same hits; half the iterations, which is what a CPU device pays for (docs/benchmarks.md).
// collapseBvh only makes trees whose traversal fits kBvhStackSize entries.

// Compare-exchange of (key, child) pairs: ascending keys.
void wideBvhSortPair(inout float ka, inout uint ca, inout float kb, inout uint cb) {
  bool swap = kb < ka;
  float k = ka;
  uint c = ca;
  ka = swap ? kb : ka;
  ca = swap ? cb : ca;
  kb = swap ? k : kb;
  cb = swap ? c : cb;
}

bool traceWideBvh(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit, out float tHit, out vec2 uvHit,
                  out uint triHit) {
  vec3 invDir = safeInverse(dir);
  uvec3 axes = shearAxes(dir);
  uint stack[kBvhStackSize];
  uint size = 0u;
  uint entry = 0u;  // the root: inner node 0
  bool found = false;
  float tBest = tMax;
  uvHit = vec2(0.0);
  triHit = 0u;
  while (true) {
    if ((entry & kWideBvhLeaf) != 0u) {
      uint first = (entry & ~kWideBvhLeaf) >> kWideBvhFirstShift;
      if (bvhTestLeaf(first, entry & kWideBvhMaxLeafCount, origin, dir, invDir, axes, tMin, tMax, anyHit, found, tBest,
                      uvHit, triHit)) {
        tHit = tBest;
        return true;
      }
    } else {
      int base = 8 * int(entry);
      vec4 near, far;
      slabIntervals4(texelVec4(wideBvhTexels, base), texelVec4(wideBvhTexels, base + 1),
                     texelVec4(wideBvhTexels, base + 2), texelVec4(wideBvhTexels, base + 3),
                     texelVec4(wideBvhTexels, base + 4), texelVec4(wideBvhTexels, base + 5), origin, invDir, near, far);
      uvec4 child = texelFetch(wideBvhTexels, base + 6);
      bvec4 hit = lessThanEqual(max(near, vec4(tMin)), min(far, vec4(tBest)));
      // Misses sort last: their key is above every hit's.
      vec4 key = mix(vec4(kInfinity), min(near, vec4(3.4e38)), hit);
      float k0 = key.x, k1 = key.y, k2 = key.z, k3 = key.w;
      uint c0 = child.x, c1 = child.y, c2 = child.z, c3 = child.w;
      wideBvhSortPair(k0, c0, k1, c1);
      wideBvhSortPair(k2, c2, k3, c3);
      wideBvhSortPair(k0, c0, k2, c2);
      wideBvhSortPair(k1, c1, k3, c3);
      wideBvhSortPair(k1, c1, k2, c2);
      uint hits = uint(hit.x) + uint(hit.y) + uint(hit.z) + uint(hit.w);
      if (hits > 0u) {
        if (size + hits - 1u > kBvhStackSize) break;
        if (hits > 3u) stack[size++] = c3;
        if (hits > 2u) stack[size++] = c2;
        if (hits > 1u) stack[size++] = c1;
        entry = c0;
        continue;
      }
    }
    if (size == 0u) break;
    entry = stack[--size];
  }
  return bvhFinishHit(found, anyHit, origin, dir, tBest, triHit, tHit);
}

// anyHit: stop at the first accepted hit. Returns whether anything was hit in (tMin, tMax) and
// the closest hit (t, u, v, leaf-order triangle index).
bool traceBvh(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit, out float tHit, out vec2 uvHit,
              out uint triHit) {
  if (kSpecWideBvhValue != 0u) return traceWideBvh(origin, dir, tMin, tMax, anyHit, tHit, uvHit, triHit);
  vec3 invDir = safeInverse(dir);
  uvec3 axes = shearAxes(dir);
  uint stack[kBvhStackSize];
  uint size = 0u;
  uint node = 0u;
  bool found = false;
  float tBest = tMax;
  uvHit = vec2(0.0);
  triHit = 0u;
  while (true) {
    GpuBvhNode n = loadBvhNode(node);
    uint count = floatBitsToUint(n.rightMinCount.w);
    if (count > 0u) {
      if (bvhTestLeaf(floatBitsToUint(n.rightMaxFirst.w), count, origin, dir, invDir, axes, tMin, tMax, anyHit, found,
                      tBest, uvHit, triHit)) {
        tHit = tBest;
        return true;
      }
    } else {
      vec2 l = slabInterval(n.leftMinLeftIndex.xyz, n.leftMaxRightIndex.xyz, origin, invDir);
      vec2 r = slabInterval(n.rightMinCount.xyz, n.rightMaxFirst.xyz, origin, invDir);
      bool hitLeft = max(l.x, tMin) <= min(l.y, tBest);
      bool hitRight = max(r.x, tMin) <= min(r.y, tBest);
      uint leftNode = floatBitsToUint(n.leftMinLeftIndex.w);
      uint rightNode = floatBitsToUint(n.leftMaxRightIndex.w);
      if (hitLeft && hitRight) {
        bool leftFirst = l.x <= r.x;
        if (size == kBvhStackSize) break;
        stack[size++] = leftFirst ? rightNode : leftNode;
        node = leftFirst ? leftNode : rightNode;
        continue;
      }
      if (hitLeft || hitRight) {
        node = hitLeft ? leftNode : rightNode;
        continue;
      }
    }
    if (size == 0u) break;
    node = stack[--size];
  }
  return bvhFinishHit(found, anyHit, origin, dir, tBest, triHit, tHit);
}

// A closest-hit query's record: (t, u, v, triangle bits), or t = -1 for a miss.
HitRecord closestHitRecord(bool found, float t, vec2 uv, uint triangle) {
  HitRecord hit;
  hit.tuvTriangle = found ? vec4(t, uv, uintBitsToFloat(triangle)) : vec4(-1.0, 0.0, 0.0, uintBitsToFloat(0u));
  return hit;
}

// Closest hit in (tMin, tMax); tMin must be >= 0 (a miss is reported as t = -1).
// hit.tuvTriangle = (t, u, v, uintBitsToFloat(triangle in leaf order)).
bool traceClosest(vec3 origin, vec3 dir, float tMin, float tMax, out HitRecord hit) {
  float t;
  vec2 uv;
  uint tri;
  bool found = traceBvh(origin, dir, tMin, tMax, false, t, uv, tri);
  hit = closestHitRecord(found, t, uv, tri);
  return found;
}

// Whether anything blocks the ray in (tMin, tMax) (shadow rays).
bool traceAny(vec3 origin, vec3 dir, float tMin, float tMax) {
  float t;
  vec2 uv;
  uint tri;
  return traceBvh(origin, dir, tMin, tMax, true, t, uv, tri);
}
#endif
