// Ellipsoidal path connections (THEORY.md §4; Pediredla et al. 2019): sample a point x on the
// scene's surfaces with |x - f1| + |f2 - x| = s' exactly, and weight it so that
//     E[g(x) * weight] = integral over the surfaces of delta(L(x) - s') g(x) dA(x),
// L(x) = |x - f1| + |x - f2|. Needs lib/common.glsl and lib/bindings.glsl (triangles, BVH, frame).
//
// API
//   struct EllipsoidSample { vec3 position; uint triangle; vec2 barycentrics; float weight; };
//   bool sampleEllipsoidConnection(vec3 f1, vec3 f2, float sPrime, vec4 u, out EllipsoidSample es);
//       Picks one triangle the shell meets with probability P_t, then phi uniformly over its arcs.
//       weight = 1 / (pdf_l * |P_T grad L|), pdf_l = P_t / (Phi_t |x'(phi)|) the density per unit
//       curve length. Returns false (weight 0, never NaN) when s' <= |f2 - f1| or the choice finds
//       no surface. position lies on the ellipsoid (the path length is s' to float precision);
//       barycentrics (u, v) follow the hit convention p = (1-u-v) p0 + u p1 + v p2; triangle is in
//       BVH leaf order. How P_t comes about is kSpecEllipsoidSelection's:
//       - kEllipsoidDescend: from the root, one child at a time with probability proportional to
//         ellipsoidBoxImportance (a conservative estimate of the curve length inside its box, zero
//         only where the shell cannot reach), then a triangle of the leaf with probability
//         w_t / sum over the leaf (w_t: an estimate of its clipped arc length). Cost: the tree's
//         depth, logarithmic in the triangle count. A descent can end in a leaf none of whose
//         triangles the shell meets (the box test is conservative): that sample is empty, which
//         keeps the estimate unbiased since every met triangle keeps a positive P_t.
//       - kEllipsoidEnumerate: over every triangle the shell meets, P_t = w_t / sum(w) (the
//         lowest-variance choice by arc length; cost grows with the triangles the shell crosses).
//         The reference the descent is tested against.
//       Random numbers: u.y picks phi; the k-th discrete decision (a descent level, a leaf
//       triangle, or the k-th candidate of the enumeration's reservoir) uses
//       hash4(bits(u.x), bits(u.z), k, bits(u.w)) (lib/rng.glsl), so decisions are independent of
//       each other and of phi for any scene size (a re-scaled single uniform would run out of bits).
//   bool sampleEllipsoidConnectionStratified(vec3 f1, vec3 f2, float sPrime, vec4 u, float line,
//                                            out EllipsoidSample es);
//       The same choice with the same probabilities, made by inversion of one uniform `line` (in
//       [0, 1); < 0: as above) while it has bits left: each decision takes the share of [0, 1)
//       its probability gives it and rescales `line` to [0, 1) within that share, and phi is what
//       is left. Samples whose `line` values are stratified (rng.glsl stratifiedUnit) are then
//       stratified along the whole curve the shell cuts from the scene, in tree order. Once the
//       decisions so far have probability below kLineMinShare the number has under 12 bits left,
//       and the hash decides the rest and u.y phi.
//   float ellipsoidConnectionDensity(vec3 f1, vec3 f2, float sPrime, uint triangle, vec3 position);
//       1 / weight of the sample that lands at `position` on `triangle` (0 if it cannot be chosen).
//       Descent: walks the one root-to-leaf path holding `triangle` (interior nodes store where
//       their right subtree's triangles begin); enumeration: one traversal to know sum(w). For MIS
//       and tests.
//   bool ellipseOnTriangle(vec3 f1, vec3 f2, float sPrime, vec3 p0, vec3 p1, vec3 p2, out EllipseArcs arcs);
//       The per-triangle conic without the BVH (GPU-vs-CPU tests; tests/support/ellipsoid_reference
//       is its double-precision twin and must stay in step with it).
//
// Mathematics. a = s'/2, c = |f2 - f1|/2, b = sqrt((a - c)(a + c)). With centre m and the frame
// u1 = (f2 - f1)/|f2 - f1|, u2, u3, the ellipsoid is x = m + M y, M = [u1 u2 u3] diag(a, b, b),
// |y| = 1. The triangle's plane n.(x - p0) = 0 becomes n'.y = d', n' = M^T n, d' = -n.(m - p0): a
// circle on the unit sphere, centre t n'/|n'| with t = d'/|n'|, radius r = sqrt((1-|t|)(1+|t|)). In
// 3D: x(phi) = p0 + C + A cos(phi) + B sin(phi). Barycentrics are affine in x, so each is
// alpha + beta cos(phi) + gamma sin(phi); their zeros (at most 6) split the circle, and the pieces
// whose midpoints are inside form at most 3 disjoint arcs of total angle Phi_t.
// Co-area factor in closed form: since grad L is normal to the ellipsoid, whose normal is
// M^-T y, the identity (M^-T a) x (M^-T b) = M (a x b) / det M gives
//     |x'(phi)| / |P_T grad L| = |x - f1| |x - f2| |n| / (2 |M^T n|),
// which has no r in it: it stays finite when the ellipsoid becomes tangent to the plane (r -> 0,
// |P_T grad L| -> 0) and needs no special case for f1 = f2 (a sphere: a / 2).
#ifndef VKTG_ELLIPSOID_GLSL
#define VKTG_ELLIPSOID_GLSL
#include "lib/rng.glsl"
#include "lib/specialization.glsl"

const uint kEllipseMaxArcs = 3u;
// Midpoint nodes per arc for the arc-length estimate w_t (the selection weight; any positive value
// is unbiased, this one follows the true length closely). The CPU twin uses the same count.
const uint kEllipseWeightNodes = 4u;
const uint kEllipsoidStackSize = 64u;
const float kTwoPi = 6.28318530717958647692;
const float kLineMinShare = 1.0 / 4096.0;

// A uniform consumed decision by decision (sampleEllipsoidConnectionStratified): u < 0 once it is
// spent or when there is none; share: the probability of the decisions it has made.
struct LineDraw {
  float u, share;
};
LineDraw noLineDraw() { return LineDraw(-1.0, 1.0); }

// After a choice whose outcome took [start, start + share) of [0, 1): the line's number rescaled to
// be uniform on [0, 1) again given that outcome, or spent once its choices are too improbable.
void narrowLine(float start, float share, inout LineDraw line) {
  line.u = clamp((line.u - start) / share, 0.0, 0.99999994);
  line.share *= share;
  if (line.share < kLineMinShare) line.u = -1.0;
}

// A decision with probability weight / total of true, by the line's number or else by `xi`.
bool decideAlongLine(float weight, float total, float xi, inout LineDraw line) {
  if (line.u < 0.0) return xi * total < weight;
  float p = weight / total;
  bool taken = line.u < p;
  narrowLine(taken ? 0.0 : p, taken ? p : 1.0 - p, line);
  return taken;
}

struct EllipseArcs {
  vec3 origin;      // p0 of the triangle; the ellipse below is relative to it
  vec3 centre;      // C
  vec3 axisA;       // A = r M e1
  vec3 axisB;       // B = r M e2
  vec3 baryAlpha;   // barycentrics (l0, l1, l2)(phi) = alpha + beta cos(phi) + gamma sin(phi)
  vec3 baryBeta;
  vec3 baryGamma;
  // Vectors, not arrays: indexed by a count that varies per lane, a vector is a few selects where a
  // CPU device would keep an array in memory and gather from it lane by lane.
  vec3 arcStart;       // radians, start in [0, 2 pi); an arc may run past 2 pi
  vec3 arcLength;
  uint count;          // number of arcs
  float total;         // Phi_t: sum of arc lengths (radians)
  float weight;        // w_t: estimated clipped curve length (metres)
  float ratioScale;    // |n| / (2 |M^T n|): |x'| / |P_T grad L| = |x - f1| |x - f2| ratioScale
};

struct EllipsoidSample {
  vec3 position;
  uint triangle;
  vec2 barycentrics;
  float weight;
};

// Orthonormal u2, u3 completing unit u1 to a right-handed frame (Duff et al. 2017, branchless).
void ellipsoidFrame(vec3 u1, out vec3 u2, out vec3 u3) {
  float sgn = u1.z >= 0.0 ? 1.0 : -1.0;
  float p = -1.0 / (sgn + u1.z);
  float q = u1.x * u1.y * p;
  u2 = vec3(1.0 + sgn * u1.x * u1.x * p, sgn * q, -sgn * u1.x);
  u3 = vec3(q, sgn + u1.y * u1.y * p, -u1.y);
}

float ellipseWrapAngle(float phi) {
  float w = phi - kTwoPi * floor(phi / kTwoPi);
  return w >= kTwoPi ? 0.0 : w;
}

// atan2 to float precision. The built-in is only required to be within 4096 ulps (lavapipe's is
// off by ~1e-4 rad), which would misplace arc ends against the triangle's edges. Range reduction
// to |z| <= tan(pi/8), then the alternating series of atan to z^21 (truncation < 1e-10).
float ellipsoidAtan2(float y, float x) {
  float ax = abs(x);
  float ay = abs(y);
  float hi = max(ax, ay);
  if (!(hi > 0.0)) return 0.0;
  float z = min(ax, ay) / hi;
  float base = 0.0;
  if (z > 0.41421356) {
    z = (z - 1.0) / (z + 1.0);
    base = 0.78539816339744831;
  }
  float t = z * z;
  float p = -1.0 / 21.0;
  p = p * t + 1.0 / 19.0;
  p = p * t - 1.0 / 17.0;
  p = p * t + 1.0 / 15.0;
  p = p * t - 1.0 / 13.0;
  p = p * t + 1.0 / 11.0;
  p = p * t - 1.0 / 9.0;
  p = p * t + 1.0 / 7.0;
  p = p * t - 1.0 / 5.0;
  p = p * t + 1.0 / 3.0;
  p = p * t - 1.0;
  float r = base - z * p;
  if (ay > ax) r = 1.57079632679489662 - r;
  if (x < 0.0) r = 3.14159265358979324 - r;
  return y < 0.0 ? -r : r;
}

bool ellipseInsideAt(EllipseArcs arcs, float phi) {
  vec3 l = arcs.baryAlpha + arcs.baryBeta * cos(phi) + arcs.baryGamma * sin(phi);
  return l.x >= 0.0 && l.y >= 0.0 && l.z >= 0.0;
}

// |x'(phi)|: speed of the parametrisation (metres per radian).
float ellipseSpeed(EllipseArcs arcs, float phi) {
  return length(arcs.axisB * cos(phi) - arcs.axisA * sin(phi));
}

vec3 ellipsePoint(EllipseArcs arcs, float phi) {
  return arcs.origin + (arcs.centre + arcs.axisA * cos(phi) + arcs.axisB * sin(phi));
}

// (u, v) with p = (1-u-v) p0 + u p1 + v p2, clamped onto the triangle against rounding.
vec2 ellipseBarycentrics(EllipseArcs arcs, float phi) {
  vec3 l = max(arcs.baryAlpha + arcs.baryBeta * cos(phi) + arcs.baryGamma * sin(phi), vec3(0.0));
  return l.yz / max(l.x + l.y + l.z, 1e-30);
}

// Maps u in [0, 1) uniformly onto the kept arcs.
float ellipseArcPhi(EllipseArcs arcs, float u) {
  float target = u * arcs.total;
  for (uint i = 0u; i < kEllipseMaxArcs && i < arcs.count; ++i) {
    if (target < arcs.arcLength[i] || i + 1u == arcs.count) return arcs.arcStart[i] + min(target, arcs.arcLength[i]);
    target -= arcs.arcLength[i];
  }
  return 0.0;
}

// |x'(phi)| / |P_T grad L| at a point x of the curve (closed form, see the header).
float ellipseCoareaRatio(EllipseArcs arcs, vec3 f1, vec3 f2, vec3 x) {
  return length(x - f1) * length(x - f2) * arcs.ratioScale;
}

// Compare-exchange: (a, b) in ascending order.
void ellipseSortPair(inout float a, inout float b) {
  float lower = min(a, b);
  b = max(a, b);
  a = lower;
}

// Root i of the sorted six (low: the first three).
float ellipseRootAt(vec3 low, vec3 high, uint i) { return i < 3u ? low[i] : high[i - 3u]; }

bool ellipseOnTriangle(vec3 f1, vec3 f2, float sPrime, vec3 p0, vec3 p1, vec3 p2, out EllipseArcs arcs) {
  arcs.origin = p0;
  arcs.centre = vec3(0.0);
  arcs.axisA = vec3(0.0);
  arcs.axisB = vec3(0.0);
  arcs.baryAlpha = vec3(0.0);
  arcs.baryBeta = vec3(0.0);
  arcs.baryGamma = vec3(0.0);
  arcs.arcStart = vec3(0.0);
  arcs.arcLength = vec3(0.0);
  arcs.count = 0u;
  arcs.total = 0.0;
  arcs.weight = 0.0;
  arcs.ratioScale = 0.0;

  vec3 d = f2 - f1;
  float dist = length(d);
  if (!(sPrime > dist)) return false;  // also rejects NaN
  float a = 0.5 * sPrime;
  float c = 0.5 * dist;
  float b = sqrt((a - c) * (a + c));
  vec3 u1 = dist > 0.0 ? d / dist : vec3(0.0, 0.0, 1.0);
  vec3 u2, u3;
  ellipsoidFrame(u1, u2, u3);

  vec3 e01 = p1 - p0;
  vec3 e02 = p2 - p0;
  vec3 n = cross(e01, e02);
  float nn = dot(n, n);
  if (!(nn > 0.0)) return false;  // degenerate triangle: zero area, measure zero
  vec3 nUnit = n * inversesqrt(nn);
  vec3 m = (f1 - p0) + 0.5 * d;  // ellipsoid centre relative to p0
  vec3 np = vec3(a * dot(nUnit, u1), b * dot(nUnit, u2), b * dot(nUnit, u3));  // M^T n
  float npLen = length(np);
  if (!(npLen > 0.0)) return false;
  float t = -dot(nUnit, m) / npLen;
  float at = abs(t);
  if (!(at < 1.0)) return false;  // plane misses the ellipsoid (or touches it: measure zero)
  float r = sqrt((1.0 - at) * (1.0 + at));
  vec3 nh = np / npLen;
  vec3 e1, e2;
  ellipsoidFrame(nh, e1, e2);
  vec3 yc = t * nh;
  // M y = a y.x u1 + b (y.y u2 + y.z u3)
  arcs.centre = m + a * yc.x * u1 + b * (yc.y * u2 + yc.z * u3);
  arcs.axisA = r * (a * e1.x * u1 + b * (e1.y * u2 + e1.z * u3));
  arcs.axisB = r * (a * e2.x * u1 + b * (e2.y * u2 + e2.z * u3));
  arcs.ratioScale = 0.5 / npLen;

  // Barycentrics of a point q relative to p0: l1 = (q x e02).n / nn, l2 = (e01 x q).n / nn.
  vec3 nOver = n / nn;
  vec2 alpha = vec2(dot(cross(arcs.centre, e02), nOver), dot(cross(e01, arcs.centre), nOver));
  vec2 beta = vec2(dot(cross(arcs.axisA, e02), nOver), dot(cross(e01, arcs.axisA), nOver));
  vec2 gamma = vec2(dot(cross(arcs.axisB, e02), nOver), dot(cross(e01, arcs.axisB), nOver));
  arcs.baryAlpha = vec3(1.0 - alpha.x - alpha.y, alpha);
  arcs.baryBeta = vec3(-beta.x - beta.y, beta);
  arcs.baryGamma = vec3(-gamma.x - gamma.y, gamma);

  // Zeros of each barycentric: alpha + beta cos(phi) + gamma sin(phi) = 0, i.e. where the line
  // alpha + (beta, gamma).q = 0 cuts the unit circle: q = -alpha/rho dir +- h perp, with dir =
  // (beta, gamma)/rho, perp = (-gamma, beta)/rho, h = sqrt((rho - |alpha|)(rho + |alpha|))/rho.
  // (Algebraic, not psi +- acos(-alpha/rho): acos is imprecise near +-1 and on some drivers.)
  // The roots stay in registers: two per barycentric (a sentinel past 2 pi where it has none),
  // ordered by a fixed sorting network, so no lane indexes memory (see EllipseArcs).
  const float kNoRoot = 1e30;
  vec3 rootA = vec3(kNoRoot), rootB = vec3(kNoRoot);
  uint k = 0u;
  for (uint i = 0u; i < 3u; ++i) {
    float al = arcs.baryAlpha[i];
    float rho = length(vec2(arcs.baryBeta[i], arcs.baryGamma[i]));
    if (rho > abs(al)) {
      vec2 dir = vec2(arcs.baryBeta[i], arcs.baryGamma[i]) / rho;
      vec2 perp = vec2(-dir.y, dir.x);
      float h = sqrt((rho - abs(al)) * (rho + abs(al))) / rho;
      vec2 foot = (-al / rho) * dir;
      vec2 q0 = foot - h * perp;
      vec2 q1 = foot + h * perp;
      rootA[i] = ellipseWrapAngle(ellipsoidAtan2(q0.y, q0.x));
      rootB[i] = ellipseWrapAngle(ellipsoidAtan2(q1.y, q1.x));
      k += 2u;
    }
  }
  if (k == 0u) {
    // No crossing: the whole ellipse is inside or outside.
    if (ellipseInsideAt(arcs, 0.0)) {
      arcs.count = 1u;
      arcs.arcLength[0] = kTwoPi;
    }
  } else {
    float r0 = rootA.x, r1 = rootB.x, r2 = rootA.y, r3 = rootB.y, r4 = rootA.z, r5 = rootB.z;
    ellipseSortPair(r1, r2); ellipseSortPair(r4, r5); ellipseSortPair(r0, r2); ellipseSortPair(r3, r5);
    ellipseSortPair(r0, r1); ellipseSortPair(r3, r4); ellipseSortPair(r1, r4); ellipseSortPair(r0, r3);
    ellipseSortPair(r2, r5); ellipseSortPair(r1, r3); ellipseSortPair(r2, r4); ellipseSortPair(r2, r3);
    vec3 low = vec3(r0, r1, r2), high = vec3(r3, r4, r5);  // the k roots first, ascending
    // Intervals [roots[i], roots[i+1]) and the wrapping one; a kept interval adjacent to the
    // previous kept one extends it (zero-length intervals are transparent).
    bool prevKept = false;
    bool firstKept = false;
    bool seenFirst = false;
    for (uint i = 0u; i < 6u && i < k; ++i) {
      float start = ellipseRootAt(low, high, i);
      float len = (i + 1u < k ? ellipseRootAt(low, high, min(i + 1u, 5u)) : r0 + kTwoPi) - start;
      if (!(len > 0.0)) continue;
      bool kept = ellipseInsideAt(arcs, start + 0.5 * len);
      if (!seenFirst) { firstKept = kept; seenFirst = true; }
      if (kept) {
        if (prevKept) {
          arcs.arcLength[arcs.count - 1u] += len;
        } else if (arcs.count < kEllipseMaxArcs) {
          arcs.arcStart[arcs.count] = start;
          arcs.arcLength[arcs.count] = len;
          ++arcs.count;
        }
      }
      prevKept = kept;
    }
    if (prevKept && firstKept && arcs.count > 1u) {
      // The last arc runs through 2 pi into the first: join them.
      uint last = arcs.count - 1u;
      arcs.arcStart[0] = arcs.arcStart[last];
      arcs.arcLength[0] += arcs.arcLength[last];
      arcs.arcLength[last] = 0.0;
      arcs.arcStart[last] = 0.0;
      arcs.count = last;
    }
  }
  for (uint i = 0u; i < kEllipseMaxArcs && i < arcs.count; ++i) {
    arcs.total += arcs.arcLength[i];
    float speedSum = 0.0;
    for (uint j = 0u; j < kEllipseWeightNodes; ++j) {
      float phi = arcs.arcStart[i] + (float(j) + 0.5) / float(kEllipseWeightNodes) * arcs.arcLength[i];
      speedSum += ellipseSpeed(arcs, phi);
    }
    arcs.weight += arcs.arcLength[i] * speedSum / float(kEllipseWeightNodes);
  }
  return arcs.count > 0u && arcs.weight > 0.0 && arcs.total > 0.0;
}

// Bounds of L over a box: the lower one, dist(f1, box) + dist(f2, box), never exceeds min L
// over the box; the upper one is exact, since L is convex its maximum is at a corner. An empty box
// (lo > hi) gets an infinite lower bound.
void ellipsoidBoxPathLengths(vec3 lo, vec3 hi, vec3 f1, vec3 f2, out float lower, out float upper) {
  lower = length(max(max(lo - f1, f1 - hi), vec3(0.0))) + length(max(max(lo - f2, f2 - hi), vec3(0.0)));
  upper = 0.0;
  for (uint i = 0u; i < 8u; ++i) {
    vec3 q = vec3((i & 1u) != 0u ? hi.x : lo.x, (i & 2u) != 0u ? hi.y : lo.y, (i & 4u) != 0u ? hi.z : lo.z);
    upper = max(upper, length(q - f1) + length(q - f2));
  }
}

// Conservative box-vs-shell test: true whenever some point of the box has L(x) = s'. The slack
// covers float rounding so a box touching the shell is never lost.
bool ellipsoidShellWithin(float lower, float upper, float sPrime) {
  return lower * (1.0 - 1e-6) <= sPrime && sPrime <= upper * (1.0 + 1e-6);
}

bool ellipsoidBoxMeetsShell(vec3 lo, vec3 hi, vec3 f1, vec3 f2, float sPrime) {
  float lower, upper;
  ellipsoidBoxPathLengths(lo, hi, f1, f2, lower, upper);
  return ellipsoidShellWithin(lower, upper, sPrime);
}

// One traversal over every triangle the shell meets. Returns sum(w). With `pick`, keeps one
// triangle with probability w_t / sum(w) (weighted reservoir, decisions from hash4(key with z =
// candidate counter)); otherwise records the arcs of triangle `target`. The result is in `chosen`.
float ellipsoidTraverse(vec3 f1, vec3 f2, float sPrime, bool pick, uvec4 key, inout LineDraw line, uint target,
                        out EllipseArcs chosen, out uint chosenTriangle) {
  chosenTriangle = 0xffffffffu;
  chosen.count = 0u;
  chosen.total = 0.0;
  chosen.weight = 0.0;
  float sum = 0.0;
  if (frame.sceneCounts.x == 0u || !(sPrime > length(f2 - f1))) return 0.0;
  uint stack[kEllipsoidStackSize];
  uint top = 0u;
  stack[top++] = 0u;
  uint candidate = 0u;
  while (top > 0u) {
    GpuBvhNode node = loadBvhNode(stack[--top]);
    uint count = floatBitsToUint(node.rightMinCount.w);
    if (count > 0u) {
      uint first = floatBitsToUint(node.rightMaxFirst.w);
      for (uint i = first; i < first + count; ++i) {
        GpuTriangle tri = loadTriangle(i);
        EllipseArcs arcs;
        if (!ellipseOnTriangle(f1, f2, sPrime, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, arcs)) continue;
        sum += arcs.weight;
        if (pick) {
          float xi = bitsToUnit(hash4(uvec4(key.x, key.y, candidate, key.w)).x);
          ++candidate;
          if (decideAlongLine(arcs.weight, sum, xi, line)) { chosen = arcs; chosenTriangle = i; }
        } else if (i == target) {
          chosen = arcs;
          chosenTriangle = i;
        }
      }
      continue;
    }
    // Push the children meeting the shell (a full stack drops the subtree: 64 levels exceed any
    // SAH tree vktg builds).
    if (ellipsoidBoxMeetsShell(node.rightMinCount.xyz, node.rightMaxFirst.xyz, f1, f2, sPrime) &&
        top < kEllipsoidStackSize)
      stack[top++] = floatBitsToUint(node.leftMaxRightIndex.w);
    if (ellipsoidBoxMeetsShell(node.leftMinLeftIndex.xyz, node.leftMaxRightIndex.xyz, f1, f2, sPrime) &&
        top < kEllipsoidStackSize)
      stack[top++] = floatBitsToUint(node.leftMinLeftIndex.w);
  }
  return sum;
}

// Descent weight of a box: 0 when no point of it has L(x) = s' (ellipsoidShellWithin's bounds,
// so every box holding a met triangle stays positive); otherwise its diagonal, a bound on the
// curve length a flat surface patch inside can hold, times a tent in where s' falls between the
// box's least and greatest path length (a shell grazing a corner crosses little of the box). The
// floor keeps a loose lower bound (a focus inside the box) from starving a box.
const float kEllipsoidTentFloor = 0.02;
float ellipsoidBoxImportance(vec3 lo, vec3 hi, vec3 f1, vec3 f2, float sPrime) {
  float lower, upper;
  ellipsoidBoxPathLengths(lo, hi, f1, f2, lower, upper);
  if (!ellipsoidShellWithin(lower, upper, sPrime)) return 0.0;
  float span = upper - lower;
  float tent = span > 0.0 ? clamp(2.0 * min(sPrime - lower, upper - sPrime) / span, 0.0, 1.0) : 1.0;
  return max(length(hi - lo), 1e-30) * (kEllipsoidTentFloor + tent);
}

// The leaf-level choice of the descent: among the leaf's triangles the shell meets, one with
// probability w_t / sum (a weighted reservoir whose k-th candidate decides with decision
// `decision` + k of the key), or (pick false) the arcs of `target`. Returns the probability of
// the choice (0 when the shell meets nothing there).
float ellipsoidLeafChoice(GpuBvhNode node, vec3 f1, vec3 f2, float sPrime, bool pick, uvec4 key, uint decision,
                          inout LineDraw line, uint target, out EllipseArcs chosen, out uint chosenTriangle) {
  chosenTriangle = 0xffffffffu;
  chosen.count = 0u;
  chosen.total = 0.0;
  chosen.weight = 0.0;
  uint count = floatBitsToUint(node.rightMinCount.w);
  uint first = floatBitsToUint(node.rightMaxFirst.w);
  float sum = 0.0;
  for (uint i = first; i < first + count; ++i) {
    GpuTriangle tri = loadTriangle(i);
    EllipseArcs arcs;
    if (!ellipseOnTriangle(f1, f2, sPrime, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, arcs)) continue;
    sum += arcs.weight;
    float xi = bitsToUnit(hash4(uvec4(key.x, key.y, decision++, key.w)).x);
    bool take = pick ? decideAlongLine(arcs.weight, sum, xi, line) : i == target;
    if (take) {
      chosen = arcs;
      chosenTriangle = i;
    }
  }
  return chosenTriangle != 0xffffffffu && sum > 0.0 ? chosen.weight / sum : 0.0;
}

// Stochastic descent (pick) or the probability of reaching `target` (pick false): returns the
// probability of the root-to-leaf choices times the leaf choice, 0 when it ends empty.
float ellipsoidDescend(vec3 f1, vec3 f2, float sPrime, bool pick, uvec4 key, inout LineDraw line, uint target,
                       out EllipseArcs chosen, out uint chosenTriangle) {
  chosenTriangle = 0xffffffffu;
  chosen.count = 0u;
  chosen.total = 0.0;
  chosen.weight = 0.0;
  if (frame.sceneCounts.x == 0u || !(sPrime > length(f2 - f1))) return 0.0;
  float probability = 1.0;
  uint index = 0u;
  // Depth is bounded by the builder (BvhBuildOptions::maxDepth); the cap only guards a corrupt tree.
  for (uint level = 0u; level < kEllipsoidStackSize; ++level) {
    GpuBvhNode node = loadBvhNode(index);
    if (floatBitsToUint(node.rightMinCount.w) > 0u)
      return probability *
             ellipsoidLeafChoice(node, f1, f2, sPrime, pick, key, level, line, target, chosen, chosenTriangle);
    float left = ellipsoidBoxImportance(node.leftMinLeftIndex.xyz, node.leftMaxRightIndex.xyz, f1, f2, sPrime);
    float right = ellipsoidBoxImportance(node.rightMinCount.xyz, node.rightMaxFirst.xyz, f1, f2, sPrime);
    float total = left + right;
    if (!(total > 0.0)) return 0.0;
    bool goRight = pick ? !decideAlongLine(left, total, bitsToUnit(hash4(uvec4(key.x, key.y, level, key.w)).x), line)
                        : target >= floatBitsToUint(node.rightMaxFirst.w);
    float share = goRight ? right : left;
    if (!(share > 0.0)) return 0.0;
    probability *= share / total;
    index = floatBitsToUint(goRight ? node.leftMaxRightIndex.w : node.leftMinLeftIndex.w);
  }
  return 0.0;
}

// The chosen triangle's arcs and the probability of choosing it, by the specialised selection.
float ellipsoidChooseTriangle(vec3 f1, vec3 f2, float sPrime, bool pick, uvec4 key, inout LineDraw line, uint target,
                              out EllipseArcs chosen, out uint chosenTriangle) {
  if (kSpecEllipsoidSelectionValue == kEllipsoidDescend)
    return ellipsoidDescend(f1, f2, sPrime, pick, key, line, target, chosen, chosenTriangle);
  float sum = ellipsoidTraverse(f1, f2, sPrime, pick, key, line, target, chosen, chosenTriangle);
  return chosenTriangle != 0xffffffffu && sum > 0.0 ? chosen.weight / sum : 0.0;
}

bool sampleEllipsoidConnectionStratified(vec3 f1, vec3 f2, float sPrime, vec4 u, float lineU, out EllipsoidSample es) {
  es.position = vec3(0.0);
  es.triangle = 0xffffffffu;
  es.barycentrics = vec2(0.0);
  es.weight = 0.0;
  EllipseArcs arcs;
  uint tri;
  uvec4 key = uvec4(floatBitsToUint(u.x), floatBitsToUint(u.z), 0u, floatBitsToUint(u.w));
  LineDraw line = LineDraw(lineU, 1.0);
  float probability = ellipsoidChooseTriangle(f1, f2, sPrime, true, key, line, 0u, arcs, tri);
  if (tri == 0xffffffffu || !(probability > 0.0)) return false;
  float phi = ellipseArcPhi(arcs, line.u >= 0.0 ? line.u : u.y);
  es.position = ellipsePoint(arcs, phi);
  es.triangle = tri;
  es.barycentrics = ellipseBarycentrics(arcs, phi);
  float w = arcs.total * ellipseCoareaRatio(arcs, f1, f2, es.position) / probability;
  if (!(w > 0.0) || isinf(w)) return false;
  es.weight = w;
  return true;
}

bool sampleEllipsoidConnection(vec3 f1, vec3 f2, float sPrime, vec4 u, out EllipsoidSample es) {
  return sampleEllipsoidConnectionStratified(f1, f2, sPrime, u, -1.0, es);
}

float ellipsoidConnectionDensity(vec3 f1, vec3 f2, float sPrime, uint triangle, vec3 position) {
  EllipseArcs arcs;
  uint tri;
  LineDraw none = noLineDraw();
  float probability = ellipsoidChooseTriangle(f1, f2, sPrime, false, uvec4(0u), none, triangle, arcs, tri);
  if (tri != triangle || !(probability > 0.0)) return 0.0;
  float density = probability / (arcs.total * ellipseCoareaRatio(arcs, f1, f2, position));
  return (density > 0.0 && !isinf(density)) ? density : 0.0;
}
#endif
