// GPU vs CPU twin: the pieces of the edge-sample weight in shaders/lib/edge.glsl (THEORY.md §3,
// visibility boundary) on random edges, directions and velocities:
//  - whether a line along w through the edge point grazes a silhouette, and on which side it is
//    unoccluded (n_p): the twin offsets the line by ±delta across the plane of edge and w and
//    intersects it with each face's half-plane: a silhouette has exactly one side that hits a face;
//  - the edge's normal velocity relative to the segment, v_n: the twin differentiates (central
//    differences in double) the signed distance of x_b from the plane through x_a and the moving
//    edge, which is the shadow plane's velocity at x_b, and scales it to y (d_a / (d_a + d_b)):
//    an independent route to the GPU's interpolation formula.
// Tolerances: float rounding of O(1) inputs, amplified by 1/sin(phi) where the plane of edge and w
// is ill-defined: |gpu - twin| <= 16 eps_float (|v_y| + |v_a| + |v_b|) / sin(phi)
// (a few roundings of each input; the measured worst is printed).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <random>

#include <glm/glm.hpp>

#include "support/gpu_test.h"
#include "vktg/silhouette_edges.h"

namespace vktg::test {
namespace {

using glm::dvec3;

struct EdgeWeightIn {
  float a0[3], a1[3], inward0[3], inward1[3], u0[3], u1[3], t, w[3], dA, dB, vA[3], vB[3], pad[2];
};
struct EdgeWeightOut {
  uint32_t silhouette;
  float np[3], sinPhi, vn;
};
static_assert(sizeof(EdgeWeightIn) == 128 && sizeof(EdgeWeightOut) == 24);

dvec3 d3(const float* v) { return dvec3(v[0], v[1], v[2]); }
void put(float* out, dvec3 v) {
  out[0] = float(v.x);
  out[1] = float(v.y);
  out[2] = float(v.z);
}

// Whether the line y + offset + s w (s any real) enters the half-plane of a face: points
// a0 + alpha e + beta inward with beta > 0.
bool lineHitsFace(dvec3 y, dvec3 offset, dvec3 w, dvec3 e, dvec3 inward) {
  dvec3 n = glm::cross(e, inward);
  double wn = glm::dot(w, n);
  double s = -glm::dot(offset, n) / wn;
  dvec3 p = offset + s * w;  // relative to y
  return glm::dot(p, inward) > 0.0;
}

struct Twin {
  bool silhouette = false;
  dvec3 np{0.0};
  double sinPhi = 0, vn = 0;
};

Twin twin(const EdgeWeightIn& in, bool boundaryEdge) {
  Twin r;
  dvec3 a0 = d3(in.a0), a1 = d3(in.a1), w = d3(in.w), e = a1 - a0;
  dvec3 y = a0 + double(in.t) * e;
  dvec3 c = glm::normalize(glm::cross(e, w));
  r.sinPhi = glm::length(glm::cross(glm::normalize(e), w));
  const double delta = 1e-6;
  auto hits = [&](double sign) {
    bool hit = lineHitsFace(y, sign * delta * c, w, e, d3(in.inward0));
    if (!boundaryEdge) hit = hit || lineHitsFace(y, sign * delta * c, w, e, d3(in.inward1));
    return hit;
  };
  bool plus = hits(1.0), minus = hits(-1.0);
  r.silhouette = plus != minus;
  if (!r.silhouette) return r;
  r.np = plus ? -c : c;
  // Signed distance of x_b from the plane through x_a and the edge, as everything moves by h.
  double dA = in.dA, dB = in.dB;
  dvec3 xa = y - dA * w, xb = y + dB * w;
  auto distance = [&](double h) {
    dvec3 b0 = a0 + h * d3(in.u0), b1 = a1 + h * d3(in.u1);
    dvec3 pa = xa + h * d3(in.vA), pb = xb + h * d3(in.vB);
    dvec3 m = glm::normalize(glm::cross(b1 - b0, pa - b0));
    if (glm::dot(glm::normalize(glm::cross(e, xa - a0)), r.np) < 0.0) m = -m;
    return glm::dot(pb - pa, m);
  };
  const double h = 1e-5;
  double rate = (distance(h) - distance(-h)) / (2.0 * h);
  r.vn = -rate * dA / (dA + dB);
  return r;
}

dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return glm::normalize(dvec3(n(rng), n(rng), n(rng)));
}

TEST(GpuEdge, SilhouettePlaneAndNormalVelocityMatchTwin) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), unit(0.0, 1.0), dist(0.3, 3.0);
  const int n = 4096;
  std::vector<EdgeWeightIn> inputs;
  std::vector<bool> boundary;
  while (int(inputs.size()) < n) {
    EdgeWeightIn in{};
    dvec3 a0(uni(rng), uni(rng), uni(rng)), a1(uni(rng), uni(rng), uni(rng));
    dvec3 e = a1 - a0;
    if (glm::length(e) < 0.2) continue;
    dvec3 along = glm::normalize(e);
    auto perpendicular = [&] { dvec3 r = randomUnit(rng); return glm::normalize(r - glm::dot(r, along) * along); };
    dvec3 i0 = perpendicular(), i1 = perpendicular(), w = randomUnit(rng);
    bool isBoundary = unit(rng) < 0.25;
    if (isBoundary) i1 = dvec3(0.0);
    // Keep configurations whose answer float rounding cannot flip: w not along the edge or in a
    // face's plane, faces not within rounding of the plane of edge and w.
    dvec3 c = glm::normalize(glm::cross(e, w));
    if (glm::length(glm::cross(along, w)) < 1e-2) continue;
    if (std::abs(glm::dot(w, glm::normalize(glm::cross(e, i0)))) < 1e-2) continue;
    if (std::abs(glm::dot(i0, c)) < 1e-3) continue;
    if (!isBoundary && (std::abs(glm::dot(i1, c)) < 1e-3 ||
                        std::abs(glm::dot(w, glm::normalize(glm::cross(e, i1)))) < 1e-2))
      continue;
    put(in.a0, a0);
    put(in.a1, a1);
    put(in.inward0, i0);
    put(in.inward1, i1);
    put(in.u0, dvec3(uni(rng), uni(rng), uni(rng)));
    put(in.u1, dvec3(uni(rng), uni(rng), uni(rng)));
    in.t = float(unit(rng));
    put(in.w, w);
    in.dA = float(dist(rng));
    in.dB = float(dist(rng));
    put(in.vA, dvec3(uni(rng), uni(rng), uni(rng)));
    put(in.vB, dvec3(uni(rng), uni(rng), uni(rng)));
    inputs.push_back(in);
    boundary.push_back(isBoundary);
  }
  auto out = runKernel<EdgeWeightOut>("edge_weight", inputs, n, n);
  int silhouettes = 0, mismatched = 0, velocityFailures = 0;
  double worstRatio = 0;
  const double eps = std::ldexp(1.0, -23);
  for (int i = 0; i < n; ++i) {
    Twin t = twin(inputs[i], boundary[i]);
    const EdgeWeightOut& g = out[i];
    if (bool(g.silhouette) != t.silhouette) {
      if (++mismatched <= 5) ADD_FAILURE() << "case " << i << ": gpu silhouette " << g.silhouette << ", twin " << t.silhouette;
      continue;
    }
    if (!t.silhouette) continue;
    ++silhouettes;
    EXPECT_GT(glm::dot(dvec3(g.np[0], g.np[1], g.np[2]), t.np), 0.999) << "case " << i << ": n_p points to the other side";
    EXPECT_NEAR(g.sinPhi, t.sinPhi, 64 * eps) << "case " << i;
    double scale = glm::length(glm::mix(d3(inputs[i].u0), d3(inputs[i].u1), double(inputs[i].t))) +
                   glm::length(d3(inputs[i].vA)) + glm::length(d3(inputs[i].vB));
    double bound = 16 * eps * scale / t.sinPhi;
    double ratio = std::abs(g.vn - t.vn) / bound;
    worstRatio = std::max(worstRatio, ratio);
    if (ratio > 1.0 && ++velocityFailures <= 5)
      ADD_FAILURE() << "case " << i << ": v_n gpu " << g.vn << ", twin " << t.vn << " (bound " << bound << ")";
  }
  EXPECT_EQ(mismatched, 0);
  EXPECT_EQ(velocityFailures, 0);
  // Both answers must occur often: a test that only ever saw one of them would prove little.
  EXPECT_GT(silhouettes, n / 5);
  EXPECT_LT(silhouettes, n - n / 5);
  std::printf("  %d cases, %d silhouettes; worst |v_n error| / bound %.3g\n", n, silhouettes, worstRatio);
}

// Edge selection on the device (selectEdge, placeInEdgeInterval) reads the fixed-point CDF the
// host writes (vktg/silhouette_edges.h) exactly: on the creases of a bumpy 300 x 300 heightfield
// (about 270k edges), the first, middle and last selection numbers of an edge's interval select
// it and fall at (u - start) / width within it; a lone edge owns all 2^32 numbers.
TEST(GpuEdge, SelectionFindsTheEdgeWhoseIntervalHoldsTheNumber) {
  const int n = 300;
  std::string heights;
  for (int i = 0; i < n * n; ++i) heights += (i ? ", " : "") + std::to_string(0.1 * std::sin(0.37 * i));
  const Scene scene = parseSceneJson(R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 2, 3], "look_at": [0, 0, 0], "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "lights": [{"type": "point", "position": [0, 2, 2], "intensity": 1}],
    "shapes": [{"name": "ground", "type": "heightfield", "resolution": [300, 300], "size": [2, 2], "material": "m",
                "heights": [)" + heights + "]}]}", "bumpy.json", ".");
  gpu::GpuEdge lone{};  // its end, 2^32, stored as 0
  for (const std::vector<gpu::GpuEdge>& edges : {silhouetteEdges(prepareScene(scene)), std::vector<gpu::GpuEdge>{lone}}) {
    SCOPED_TRACE(std::to_string(edges.size()) + " edges");
    std::vector<uint32_t> numbers, expectedEdge;
    std::vector<double> expectedPlace;
    uint64_t start = 0;
    for (size_t e = 0; e < edges.size(); ++e) {
      const uint64_t end = e + 1 == edges.size() ? uint64_t(1) << 32 : std::bit_cast<uint32_t>(edges[e].inward0.w);
      if (e % 97 == 0 || e + 1 == edges.size())
        for (uint64_t u : {start, start + (end - start - 1) / 2, end - 1}) {
          numbers.push_back(uint32_t(u));
          expectedEdge.push_back(uint32_t(e));
          expectedPlace.push_back(double(u - start) / double(end - start));
        }
      start = end;
    }
    const uint32_t count = uint32_t(numbers.size());
    const std::vector<uint32_t> out = runKernelWords("edge_select", numbers, 2 * size_t(count), count, nullptr,
                                                     gpu::kEllipsoidDescend, &edges);
    int failures = 0;
    for (uint32_t i = 0; i < count && failures < 5; ++i) {
      const float place = std::bit_cast<float>(out[2 * i + 1]);
      // Three float roundings (two conversions and the division) of a place in [0, 1].
      if (out[2 * i] == expectedEdge[i] && std::abs(place - expectedPlace[i]) <= 3e-7 && place <= 1.0f) continue;
      ADD_FAILURE() << "number " << numbers[i] << ": edge " << out[2 * i] << " at " << place << ", expected edge "
                    << expectedEdge[i] << " at " << expectedPlace[i];
      ++failures;
    }
    EXPECT_EQ(failures, 0);
  }
}

}  // namespace
}  // namespace vktg::test
