// Statistical tests of light sampling (sampleLight, shaders/lib/lights.glsl) through
// tests/shaders/light_sample.comp, on a scene of emissive triangles with different areas and
// radiances, a non-emissive triangle and two point lights:
//  1. Selection: how often each light is chosen matches the power-proportional pmf computed here
//     from the scene definition (area light pi Le A, point light 4 pi I) — chi-square.
//  2. Position: the points on each triangle are uniform in area — chi-square of the barycentric
//     coordinates against the uniform density.
//  3. Per sample: pdf equals pmf / area (area lights) or pmf (point lights); emission, normal
//     and position are the light's.
// Every triangle lies in its own plane z = const, so a sample is attributed to its light by
// geometry, independent of the order of the GPU's light and triangle buffers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "support/chi2.h"
#include "support/gpu_test.h"

namespace vktg::test {
namespace {

struct LightIn {
  float u[3], pad;
};
struct LightOut {
  uint32_t ok, isPoint;
  float position[3], normal[3], emission, pdf;
  uint32_t pad[2];
};
static_assert(sizeof(LightIn) == 16 && sizeof(LightOut) == 48);

constexpr uint32_t kSamples = 1u << 18;
constexpr double kPi = std::numbers::pi;

struct RefTriangleLight {
  glm::dvec3 p0, p1, p2;
  double emission;
  double area() const { return 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0)); }
  glm::dvec3 normal() const { return glm::normalize(glm::cross(p1 - p0, p2 - p0)); }
};
struct RefPointLight {
  glm::dvec3 position;
  double intensity;
};

// Emitters: one per plane z = 0, 1, 2, 5; the last has no right angle. Triangles 1 and 2 belong
// to one shape (same radiance, different areas). The triangle at z = 3 does not emit.
const std::vector<RefTriangleLight> kTriangles = {
    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2.0},
    {{0, 0, 1}, {0.5, 0, 1}, {0, 0.5, 1}, 5.0},
    {{0, 0, 2}, {2, 0, 2}, {0, 1, 2}, 5.0},
    {{0, 0, 5}, {2, 0.5, 5}, {0.3, 1.7, 5}, 0.5},
};
const RefTriangleLight kDark = {{0, 0, 3}, {3, 0, 3}, {0, 3, 3}, 0.0};
const std::vector<RefPointLight> kPoints = {{{0.25, 0.5, 10}, 0.3}, {{1, 1, 12}, 0.1}};

Scene lightScene() {
  Scene scene;
  scene.materials.push_back({});
  auto addTriangle = [](Shape& shape, const RefTriangleLight& t) {
    uint32_t base = uint32_t(shape.positions.size());
    shape.positions.push_back(glm::vec3(t.p0));
    shape.positions.push_back(glm::vec3(t.p1));
    shape.positions.push_back(glm::vec3(t.p2));
    shape.triangles.push_back({base, base + 1, base + 2});
  };
  Shape a, b, d, dark;
  a.name = "a";
  a.emission = float(kTriangles[0].emission);
  addTriangle(a, kTriangles[0]);
  b.name = "b";
  b.emission = float(kTriangles[1].emission);
  addTriangle(b, kTriangles[1]);
  addTriangle(b, kTriangles[2]);
  d.name = "d";
  d.emission = float(kTriangles[3].emission);
  addTriangle(d, kTriangles[3]);
  dark.name = "dark";
  addTriangle(dark, kDark);
  scene.shapes = {a, dark, b, d};
  for (size_t i = 0; i < kPoints.size(); ++i)
    scene.pointLights.push_back({"point" + std::to_string(i), glm::vec3(kPoints[i].position), float(kPoints[i].intensity)});
  return scene;
}

// pmf over [triangles..., points...]: power-proportional.
std::vector<double> referencePmf() {
  std::vector<double> power;
  for (const auto& t : kTriangles) power.push_back(kPi * t.emission * t.area());
  for (const auto& p : kPoints) power.push_back(4 * kPi * p.intensity);
  double total = 0;
  for (double p : power) total += p;
  for (double& p : power) p /= total;
  return power;
}

// Index into [triangles..., points...] of the light a sample came from, or -1.
int identify(const LightOut& o) {
  glm::dvec3 x(o.position[0], o.position[1], o.position[2]);
  if (o.isPoint) {
    for (size_t i = 0; i < kPoints.size(); ++i)
      if (glm::length(x - kPoints[i].position) < 1e-6) return int(kTriangles.size() + i);
    return -1;
  }
  for (size_t i = 0; i < kTriangles.size(); ++i)
    if (std::abs(x.z - kTriangles[i].p0.z) < 1e-4) return int(i);
  return -1;
}

// Barycentric coordinates (b1, b2) of x in the triangle's plane: x = (1 - b1 - b2) p0 + b1 p1 + b2 p2.
glm::dvec2 barycentrics(const RefTriangleLight& t, const glm::dvec3& x) {
  glm::dvec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, q = x - t.p0;
  double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  double q1 = glm::dot(q, e1), q2 = glm::dot(q, e2);
  double det = d11 * d22 - d12 * d12;
  return {(d22 * q1 - d12 * q2) / det, (d11 * q2 - d12 * q1) / det};
}

struct LightRun {
  std::vector<LightOut> out;
  std::vector<int> light;  // identify() per sample
};

const LightRun& lightRun() {
  static const LightRun run = [] {
    LightRun r;
    std::mt19937 rng(2024);
    std::vector<LightIn> in(kSamples);
    for (LightIn& s : in) {
      for (float& u : s.u) u = float(rng() >> 8) * (1.0f / 16777216.0f);
      s.pad = 0;
    }
    const Scene scene = lightScene();
    r.out = runKernel<LightOut>("light_sample", in, kSamples, kSamples, &scene);
    for (const LightOut& o : r.out) r.light.push_back(o.ok ? identify(o) : -1);
    return r;
  }();
  return run;
}

// 1 selection test + 1 uniformity test per triangle share the false-failure rate.
Chi2Options chi2Options() {
  Chi2Options options;
  options.testCount = 1 + int(kTriangles.size());
  return options;
}

TEST(StatLights, SelectionFollowsEmittedPower) {
  const LightRun& run = lightRun();
  const std::vector<double> pmf = referencePmf();
  // Cells: each light, then "no light / unidentified / failed" (expected never).
  std::vector<double> observed(pmf.size() + 1, 0.0), expected(pmf.size() + 1, 0.0);
  for (int l : run.light) observed[l >= 0 ? size_t(l) : pmf.size()] += 1.0;
  for (size_t i = 0; i < pmf.size(); ++i) expected[i] = pmf[i] * kSamples;
  Chi2Result r = pearsonChi2(observed, expected, chi2Options(), [&](size_t i) {
    if (i == pmf.size()) return std::string("no light (failed, or off every light)");
    return i < kTriangles.size() ? "triangle " + std::to_string(i) : "point " + std::to_string(i - kTriangles.size());
  });
  EXPECT_TRUE(r.passed) << r.report;
  EXPECT_EQ(observed.back(), 0.0) << "samples that failed or landed on no emitter (e.g. the dark triangle)";
}

TEST(StatLights, PointsAreUniformOnEachTriangle) {
  const LightRun& run = lightRun();
  // Square chart (a, b) = (b1 / (1 - b2), b2) of the triangle: uniform area density is
  // 2 (1 - b) there, smooth, so cells need not follow the diagonal b1 + b2 = 1.
  const Grid2D grid{0, 1, 0, 1, 16, 16};
  for (size_t t = 0; t < kTriangles.size(); ++t) {
    SCOPED_TRACE("triangle " + std::to_string(t));
    std::vector<glm::dvec2> samples;
    size_t outside = 0;
    for (size_t i = 0; i < run.out.size(); ++i) {
      if (run.light[i] != int(t)) continue;
      const LightOut& o = run.out[i];
      glm::dvec2 b = barycentrics(kTriangles[t], glm::dvec3(o.position[0], o.position[1], o.position[2]));
      if (b.x < -1e-5 || b.y < -1e-5 || b.x + b.y > 1 + 1e-5) ++outside;
      double b1 = std::clamp(b.x, 0.0, 1.0), b2 = std::clamp(b.y, 0.0, 1.0);
      samples.push_back({b2 < 1 ? std::clamp(b1 / (1 - b2), 0.0, 1.0) : 0.0, b2});
    }
    EXPECT_EQ(outside, 0u) << "points outside the triangle";
    ASSERT_GT(samples.size(), 1000u);
    Chi2Result r = chi2Test2D(grid, samples, samples.size(), [](double, double b) { return 2 * (1 - b); },
                              chi2Options());
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.densityMass, 1.0, 1e-6);
  }
}

TEST(StatLights, PdfIsPmfOverAreaAndFieldsAreTheLights) {
  const LightRun& run = lightRun();
  const std::vector<double> pmf = referencePmf();
  size_t checked = 0;
  for (size_t i = 0; i < run.out.size(); ++i) {
    const int l = run.light[i];
    if (l < 0) continue;
    const LightOut& o = run.out[i];
    // Float pmf and area: a few float roundings of relative error.
    if (size_t(l) < kTriangles.size()) {
      const RefTriangleLight& t = kTriangles[size_t(l)];
      const double expected = pmf[size_t(l)] / t.area();
      ASSERT_NEAR(o.pdf, expected, 1e-5 * expected) << "triangle " << l;
      ASSERT_EQ(o.emission, float(t.emission)) << "triangle " << l;
      glm::dvec3 n(o.normal[0], o.normal[1], o.normal[2]);
      ASSERT_NEAR(glm::dot(n, t.normal()), 1.0, 1e-6) << "triangle " << l;
    } else {
      const RefPointLight& p = kPoints[size_t(l) - kTriangles.size()];
      ASSERT_NEAR(o.pdf, pmf[size_t(l)], 1e-5 * pmf[size_t(l)]) << "point light " << l;
      ASSERT_EQ(o.emission, float(p.intensity)) << "point light " << l;
    }
    ++checked;
  }
  EXPECT_GT(checked, kSamples / 2);
}

}  // namespace
}  // namespace vktg::test
