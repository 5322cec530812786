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

// anyHit: stop at the first accepted hit. Returns whether anything was hit in (tMin, tMax) and
// the closest hit (t, u, v, leaf-order triangle index).
bool traceBvh(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit, out float tHit, out vec2 uvHit,
              out uint triHit) {
  vec3 invDir = safeInverse(dir);
  uvec3 axes = shearAxes(dir);
  uint stack[kBvhStackSize];
  uint size = 0u;
  uint node = 0u;
  bool found = false;
  float tBest = tMax;
  tHit = -1.0;
  uvHit = vec2(0.0);
  triHit = 0u;
  while (true) {
    GpuBvhNode n = loadBvhNode(node);
    uint count = floatBitsToUint(n.rightMinCount.w);
    if (count > 0u) {
      uint first = floatBitsToUint(n.rightMaxFirst.w);
      for (uint i = first; i < first + count; ++i) {
        GpuTriangle tri = loadTriangle(i);
        float t;
        vec2 uv;
        // Tested against the full window: a hit at exactly tBest with a smaller index still wins.
        if (!intersectTrianglePrepared(tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, origin, dir, invDir, axes, tMin, tMax, t, uv))
          continue;
        if (!found || t < tBest || (t == tBest && i < triHit)) {
          found = true;
          tBest = t;
          tHit = t;
          uvHit = uv;
          triHit = i;
          if (anyHit) return true;
        }
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
  if (found && !anyHit) {
    GpuTriangle tri = loadTriangle(triHit);
    tHit = refinedHitDistance(tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, origin, dir, tHit);
  }
  return found;
}

// Closest hit in (tMin, tMax); tMin must be >= 0 (a miss is reported as t = -1).
// hit.tuvTriangle = (t, u, v, uintBitsToFloat(triangle in leaf order)).
bool traceClosest(vec3 origin, vec3 dir, float tMin, float tMax, out HitRecord hit) {
  float t;
  vec2 uv;
  uint tri;
  bool found = traceBvh(origin, dir, tMin, tMax, false, t, uv, tri);
  hit.tuvTriangle = found ? vec4(t, uv, uintBitsToFloat(tri)) : vec4(-1.0, 0.0, 0.0, uintBitsToFloat(0u));
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
