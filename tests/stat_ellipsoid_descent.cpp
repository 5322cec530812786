// Statistical tests of the stochastic BVH descent that ellipsoidal connections use to choose a
// triangle (kEllipsoidDescend, shaders/lib/ellipsoid.glsl), on tessellated surfaces where the tree
// has real depth: a square plane and a tilted triangle above it, foci above both.
//  1. The choice: at fixed s', how often each triangle is chosen (and how often a descent ends
//     empty) against the CPU twin of the descent (tests/support/ellipsoid_reference: the same tree,
//     box weights and leaf choice in double precision), by chi-square. Given the triangle, the point
//     is placed on its arcs as in the enumeration, whose area density stat_ellipsoid.cpp tests.
//     (An area-density histogram is no test here: the descent's density has integrable 1/r peaks
//     where the shell first enters a leaf, which cell quadrature cannot integrate reliably.)
//  2. ellipsoidConnectionDensity (GPU, walking the tree to one triangle) equals 1 / weight.
//  3. Unbiasedness, independent of both: mean(weight) at fixed s' equals d/ds' of the area of
//     {x : L(x) <= s'}, by quadrature of the untessellated surfaces (tessellation changes the
//     tree, not the surface), for the descent and for the enumeration it replaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "support/chi2.h"
#include "support/ellipsoid_kernel.h"
#include "support/ellipsoid_reference.h"
#include "support/gpu_test.h"
#include "support/test_scenes.h"
#include "vktg/prepared_scene.h"

namespace vktg::test {
namespace {

// The coarse surfaces as two shapes, each triangle split `levels` times.
Scene tessellatedScene(uint32_t levels) {
  std::vector<RefTriangle> tris = planeAndTiltedTriangles();
  Shape plane = shapeOfTriangles("plane", {tris[0], tris[1]}), tilted = shapeOfTriangles("tilted", {tris[2]});
  subdivideShape(plane, levels);
  subdivideShape(tilted, levels);
  return sceneOfShapes({plane, tilted});
}

// The triangles the GPU sees, in leaf order, with the tree it descends.
struct LeafOrder {
  Bvh bvh;
  std::vector<RefTriangle> triangles;
};
LeafOrder leafOrder(const Scene& scene) {
  PreparedScene prepared = prepareScene(scene);
  LeafOrder out{prepared.bvh, {}};
  for (const gpu::GpuTriangle& t : prepared.triangles)
    out.triangles.push_back({dvec3(glm::vec3(t.p0)), dvec3(glm::vec3(t.p1)), dvec3(glm::vec3(t.p2))});
  return out;
}

std::vector<EllipsoidSampleIn> makeInputs(size_t n, uint32_t seed, double fixedS) {
  return planeAndTiltedInputs(n, seed, [fixedS](std::mt19937&) { return float(fixedS); });
}

// Input i's stratified number: point i of a golden-ratio sequence shifted by `shift`, as
// rng.glsl's stratifiedUnit draws it.
void stratify(std::vector<EllipsoidSampleIn>& in, double shift) {
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  for (size_t i = 0; i < in.size(); ++i)
    in[i].line = std::min(float(std::fmod(shift + double(i) * golden, 1.0)), 0.99999994f);
}

// How often each triangle of a 48-triangle tree is chosen at each length (and how often a descent
// ends empty), against the CPU twin's probabilities, by chi-square; `stratified`: the choices
// inverting one stratified number per sample. Its counts are closer to the expected ones than
// independent draws', which the chi-square test accepts as readily; wrong probabilities it rejects.
void expectTriangleChoicesFollowTheTree(bool stratified) {
  Scene scene = tessellatedScene(2);  // 48 triangles
  LeafOrder leaf = leafOrder(scene);
  const size_t triangles = leaf.triangles.size();
  ASSERT_EQ(triangles, 48u);
  ASSERT_GT(leaf.bvh.nodes.size(), 15u) << "the tree should be several levels deep";
  // 2.2: the tilted triangle only; then the plane as well, up to lengths where the shell leaves
  // most leaves' boxes and descents can end empty.
  const std::vector<double> lengths = {2.2, 2.9, 3.1, 3.25, 3.4, 3.7};
  Chi2Options options;
  options.testCount = int(lengths.size());
  for (double s : lengths) {
    const size_t n = 100000;
    auto in = makeInputs(n, 17 + uint32_t(s * 10), s);
    if (stratified) stratify(in, 0.1 * s);
    auto out = runKernel<EllipsoidSampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene, gpu::kEllipsoidDescend);
    // Cells: one per leaf triangle, the last one the descents that ended empty.
    std::vector<double> observed(triangles + 1, 0.0), expected(triangles + 1, 0.0);
    size_t densityMismatch = 0;
    for (size_t i = 0; i < n; ++i) {
      const EllipsoidSampleOut& o = out[i];
      if (!o.ok) {
        observed[triangles] += 1.0;
        continue;
      }
      ASSERT_TRUE(std::isfinite(o.weight) && o.weight > 0.0f) << i;
      ASSERT_LT(o.triangle, triangles) << i;
      dvec3 x(o.position[0], o.position[1], o.position[2]);
      ASSERT_NEAR(pathLengthRef(kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, x), in[i].s, 1e-5) << i;
      if (!(std::abs(double(o.density) * o.weight - 1.0) < 1e-4)) ++densityMismatch;
      observed[o.triangle] += 1.0;
    }
    EXPECT_EQ(densityMismatch, 0u) << "ellipsoidConnectionDensity != 1 / weight";
    double total = 0.0;
    for (size_t t = 0; t < triangles; ++t) {
      expected[t] = n * ellipsoidDescentProbabilityRef(leaf.bvh, leaf.triangles, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, in[0].s, t);
      total += expected[t];
    }
    expected[triangles] = std::max(double(n) - total, 0.0);
    Chi2Result r = pearsonChi2(observed, expected, options, [&](size_t c) {
      return c == triangles ? std::string("empty") : "triangle " + std::to_string(c);
    });
    EXPECT_TRUE(r.passed) << "s' = " << s << "\n" << r.report;
    std::printf("%s s' = %.2f: %zu triangles can be chosen, %.2f%% of descents end empty, p = %.3g\n",
                stratified ? "stratified" : "independent", s,
                size_t(std::count_if(expected.begin(), expected.end() - 1, [](double e) { return e > 0.0; })),
                100.0 * observed[triangles] / n, r.pValue);
  }
}

TEST(StatEllipsoidDescent, TriangleChoiceChiSquare) { expectTriangleChoicesFollowTheTree(false); }

TEST(StatEllipsoidDescent, StratifiedTriangleChoiceChiSquare) { expectTriangleChoicesFollowTheTree(true); }

// d/ds' Area{L <= s'} of the coarse surfaces by quadrature, error from halving the step and doubling rows.
struct Reference {
  double value, error;
};
Reference areaDerivative(double s) {
  std::vector<RefTriangle> tris = planeAndTiltedTriangles();
  double coarse = shellAreaDerivative(tris, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, 1e-4 * s, 3000);
  double fine = shellAreaDerivative(tris, kPlaneAndTiltedFocus1, kPlaneAndTiltedFocus2, s, 5e-5 * s, 6000);
  return {fine, std::abs(fine - coarse)};
}

TEST(StatEllipsoidDescent, MeanWeightIsAreaDerivative) {
  Scene scene = tessellatedScene(5);  // 3072 triangles
  for (uint32_t selection : {gpu::kEllipsoidDescend, gpu::kEllipsoidEnumerate}) {
    // 2.2: tilted triangle only; 2.9 and 3.1: the plane as well.
    for (double s : {2.2, 2.9, 3.1}) {
      // The enumeration's weights barely vary at fixed s': fewer draws measure it as well.
      const size_t n = selection == gpu::kEllipsoidDescend ? 1 << 17 : 1 << 14;
      auto in = makeInputs(n, 7 + uint32_t(s * 10), s);
      auto out = runKernel<EllipsoidSampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene, selection);
      double sum = 0.0, sq = 0.0;
      size_t mismatch = 0;
      for (const EllipsoidSampleOut& o : out) {
        ASSERT_TRUE(std::isfinite(o.weight));
        double w = o.ok ? o.weight : 0.0;
        sum += w;
        sq += w * w;
        if (o.ok && !(std::abs(double(o.density) * o.weight - 1.0) < 1e-4)) ++mismatch;
      }
      EXPECT_EQ(mismatch, 0u) << "ellipsoidConnectionDensity != 1 / weight";
      double mean = sum / n;
      double se = std::sqrt(std::max(sq / n - mean * mean, 0.0) / (n - 1));
      Reference ref = areaDerivative(double(in[0].s));
      ASSERT_GT(ref.value, 0.0);
      // 4.5 standard errors, the quadrature's own error, and float32 evaluation of the weight.
      double tol = 4.5 * se + 2.0 * ref.error + 256.0 * std::ldexp(1.0, -24) * ref.value;
      EXPECT_NEAR(mean, ref.value, tol) << (selection == gpu::kEllipsoidDescend ? "descend" : "enumerate") << ", s' = "
                                        << s << " se = " << se << " quadrature error = " << ref.error;
      std::printf("%s s'=%.1f: mean %.6g, reference %.6g, relative se %.3g\n",
                  selection == gpu::kEllipsoidDescend ? "descend  " : "enumerate", s, mean, ref.value, se / mean);
    }
  }
}

// Stratified numbers keep the mean weight (the area derivative) and spread the samples along the
// whole curve: the means of 64 runs of consecutive samples, each itself a stratified set, vary far
// less than independent samples' would (their variance against the variance of one weight over
// the run's length). 3072 triangles: a tree deep enough that the number runs out of bits on some
// descents and the hash finishes them.
TEST(StatEllipsoidDescent, StratifiedMeanWeightIsAreaDerivativeWithLessVariance) {
  Scene scene = tessellatedScene(5);
  for (double s : {2.2, 2.9, 3.1}) {
    const size_t n = 1 << 17, runs = 64, perRun = n / runs;
    auto in = makeInputs(n, 9 + uint32_t(s * 10), s);
    stratify(in, 0.37);
    auto out = runKernel<EllipsoidSampleOut>("ellipsoid_sample", in, n, uint32_t(n), &scene, gpu::kEllipsoidDescend);
    double sum = 0.0, sq = 0.0;
    std::vector<double> runMeans(runs, 0.0);
    size_t mismatch = 0;
    for (size_t i = 0; i < n; ++i) {
      const EllipsoidSampleOut& o = out[i];
      ASSERT_TRUE(std::isfinite(o.weight));
      double w = o.ok ? o.weight : 0.0;
      sum += w;
      sq += w * w;
      runMeans[i / perRun] += w / perRun;
      if (o.ok && !(std::abs(double(o.density) * o.weight - 1.0) < 1e-4)) ++mismatch;
    }
    EXPECT_EQ(mismatch, 0u) << "ellipsoidConnectionDensity != 1 / weight";
    const double mean = sum / n, variance = std::max(sq / n - mean * mean, 0.0);
    double spread = 0.0;
    for (double m : runMeans) spread += (m - mean) * (m - mean) / (runs - 1);
    // The independent samples' standard error bounds a stratified mean's (its error is smaller).
    const double se = std::sqrt(variance / (n - 1));
    Reference ref = areaDerivative(double(in[0].s));
    const double tol = 4.5 * se + 2.0 * ref.error + 256.0 * std::ldexp(1.0, -24) * ref.value;
    EXPECT_NEAR(mean, ref.value, tol) << "s' = " << s;
    const double ratio = spread / (variance / perRun);
    std::printf("stratified s'=%.1f: mean %.6g, reference %.6g; a run's mean varies %.3gx as much as independent "
                "samples'\n", s, mean, ref.value, ratio);
    // Independent samples: 1 (from 63 degrees of freedom, below 0.6 with probability 1e-3).
    EXPECT_LT(ratio, 0.2) << "s' = " << s;
  }
}

}  // namespace
}  // namespace vktg::test
