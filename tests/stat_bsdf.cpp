// Chi-square tests of bsdfSample (shaders/lib/bsdf.glsl) and of the warps (shaders/lib/warp.glsl):
// the directions drawn on the GPU must follow bsdfPdf as computed by the double-precision twin
// (tests/support/bsdf_reference.cpp); at every sample the GPU's own eval and pdf must reproduce
// the returned weight and pdf, and the twin's pdf must match the GPU's; the density must integrate
// to the fraction of draws that produced a sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/bsdf_reference.h"
#include "support/chi2.h"
#include "support/gpu_test.h"

namespace vktg {
namespace {

using test::Chi2Options;
using test::Chi2Result;

constexpr uint32_t kSamples = 1u << 20;
// Every chi-square test of this file shares one family-wise false-failure rate of 1%.
constexpr int kChi2Tests = 36 + 3;
constexpr double kFamilyLevel = 0.01;
constexpr int kCosBins = 40;
constexpr int kPhiBins = 80;
// Per-sample agreement of float values is bounded by test::bsdfFloatTolerance(kappa), kappa the
// twin's sensitivity to direction rounding at that sample (tests/support/bsdf_reference.h).

struct SampleIn {
  gpu::GpuMaterial material;
  float n[4];
  float wi[4];
  uint32_t seed, pad[3];
};

struct SampleOut {
  float wo[3];
  float weight;
  float pdf;
  uint32_t flags;
  float eval;
  float evalPdf;
};

struct Config {
  std::string name;
  gpu::GpuMaterial material;
  double cosWi;  // signed: negative puts wi inside the dielectric
};

std::vector<Config> configs() {
  std::vector<Config> out;
  const double cosines[] = {0.9, 0.4, 0.02};
  auto cosName = [](double c) {
    std::ostringstream s;
    s << (c < 0 ? "inside_cos" : "cos") << int(std::round(std::abs(c) * 100));
    return s.str();
  };
  for (double c : cosines) out.push_back({"diffuse_" + cosName(c), {gpu::kMaterialDiffuse, 0.7f, 0.5f, 1.0f}, c});
  for (float alpha : {0.05f, 0.3f, 1.0f})
    for (double c : cosines)
      out.push_back({"conductor_a" + std::to_string(int(std::round(alpha * 100))) + "_" + cosName(c),
                     {gpu::kMaterialConductor, 0.8f, alpha, 1.0f}, c});
  for (float alpha : {0.05f, 0.3f})
    for (float ior : {1.5f, 1.33f})
      for (double side : {1.0, -1.0})
        for (double c : cosines)
          out.push_back({"dielectric_a" + std::to_string(int(std::round(alpha * 100))) + "_ior" +
                             std::to_string(int(std::round(ior * 100))) + "_" + cosName(side * c),
                         {gpu::kMaterialDielectric, 0.9f, alpha, ior}, side * c});
  return out;
}

class BsdfSampling : public ::testing::TestWithParam<Config> {};

TEST_P(BsdfSampling, MatchesPdfAndWeights) {
  const Config& cfg = GetParam();
  // wi with a generic azimuth so that no axis of the shader's frame is special.
  double s = std::sqrt(1.0 - cfg.cosWi * cfg.cosWi);
  glm::vec3 wi(float(s * std::cos(0.7)), float(s * std::sin(0.7)), float(cfg.cosWi));
  wi = glm::normalize(wi);
  SampleIn in{cfg.material, {0, 0, 1, 0}, {wi.x, wi.y, wi.z, 0}, 1234u + uint32_t(cfg.cosWi * 1000), {}};
  std::vector<SampleOut> out =
      test::runKernel<SampleOut>("bsdf_sample", std::vector<SampleIn>{in}, kSamples, kSamples);

  const glm::dvec3 n(0, 0, 1), wid(wi);
  std::vector<glm::dvec3> dirs;
  dirs.reserve(kSamples);
  size_t weightMismatch = 0, pdfMismatch = 0, twinMismatch = 0, nonFinite = 0, transmitted = 0;
  size_t beyondPlainBound = 0;
  double worstWeight = 0, worstPdf = 0, worstTwin = 0;
  auto rel = [](double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-30); };
  for (const SampleOut& o : out) {
    if (!(o.flags & 1u)) continue;
    glm::dvec3 wo(o.wo[0], o.wo[1], o.wo[2]);
    if (!std::isfinite(o.weight) || !std::isfinite(o.pdf) || !(o.pdf > 0) || !std::isfinite(wo.x + wo.y + wo.z)) {
      ++nonFinite;
      continue;
    }
    dirs.push_back(wo);
    if (o.flags & 2u) ++transmitted;
    // The GPU's weight must be its own f |cos| / pdf at the direction it returned.
    double recomputed = double(o.eval) * std::abs(wo.z) / double(o.pdf);
    double e1 = rel(o.weight, recomputed), e2 = rel(o.evalPdf, o.pdf);
    double twin = test::bsdfPdfReference(cfg.material, n, wid, wo);
    double e3 = rel(o.pdf, twin);
    worstWeight = std::max(worstWeight, e1);
    worstPdf = std::max(worstPdf, e2);
    worstTwin = std::max(worstTwin, e3);
    // The sensitivity is only worth computing for the rare samples beyond the plain bound.
    if (std::max({e1, e2, e3}) > test::kBsdfRelTolerance) {
      double allowed = test::bsdfFloatTolerance(
          test::bsdfSensitivityReference(cfg.material, n, wid, wo, false, dirs.size()));
      ++beyondPlainBound;
      weightMismatch += e1 > allowed;
      pdfMismatch += e2 > allowed;
      twinMismatch += e3 > allowed;
    }
  }
  EXPECT_EQ(nonFinite, 0u);
  EXPECT_EQ(weightMismatch, 0u) << "worst relative error " << worstWeight;
  EXPECT_EQ(pdfMismatch, 0u) << "worst relative error " << worstPdf;
  EXPECT_EQ(twinMismatch, 0u) << "worst relative error " << worstTwin;
  if (cfg.material.type != gpu::kMaterialDielectric) {
    EXPECT_EQ(transmitted, 0u);
    // Two-sided reflection: every sample leaves on wi's side.
    for (const glm::dvec3& d : dirs) {
      ASSERT_GT(d.z * wid.z, 0.0);
    }
  }

  Chi2Options options{kFamilyLevel, kChi2Tests, 5.0};
  Chi2Result r = test::chi2Sphere(
      dirs, kSamples, [&](const glm::dvec3& w) { return test::bsdfPdfReference(cfg.material, n, wid, w); }, kCosBins,
      kPhiBins, options);
  EXPECT_TRUE(r.passed) << r.report;

  // The density integrates to the probability of producing a sample. Binomial standard error of
  // the measured fraction, 5 sigma; the quadrature error is below 1e-3 / kSamples per cell.
  double fraction = double(dirs.size()) / kSamples;
  double sigma = std::sqrt(std::max(fraction * (1 - fraction), 1.0 / kSamples) / kSamples);
  double quadrature = 1e-3 / kSamples * kCosBins * kPhiBins;
  EXPECT_NEAR(r.densityMass, fraction, 5 * sigma + quadrature) << "sampled fraction " << fraction;
  if (cfg.material.type == gpu::kMaterialDiffuse) {
    // Lambert loses no mass: only the kRefMinCos sliver of the hemisphere (2e-12) is excluded.
    EXPECT_NEAR(r.densityMass, 1.0, quadrature + 1e-9);
    EXPECT_EQ(dirs.size(), kSamples);
  }
  std::printf("%-34s chi2 %7.1f dof %4d p %.3f mass %.6f sampled %.6f worst rel: weight %.1e pdf %.1e twin %.1e "
              "(%zu beyond 1e-4, held to their conditioned bound)\n",
              cfg.name.c_str(), r.statistic, r.dof, r.pValue, r.densityMass, fraction, worstWeight, worstPdf,
              worstTwin, beyondPlainBound);
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfSampling, ::testing::ValuesIn(configs()),
                         [](const ::testing::TestParamInfo<Config>& info) { return info.param.name; });

// The test has power: the same conductor samples fail against a lobe only 5% wider, and a dielectric's
// fail against an IOR 3% off. (Not part of the Sidak family: these are meant to be rejected.)
TEST(BsdfSamplingPower, RejectsSlightlyWrongDensities) {
  struct Case {
    gpu::GpuMaterial sampled, claimed;
  };
  const Case cases[] = {
      {{gpu::kMaterialConductor, 0.8f, 0.3f, 1.0f}, {gpu::kMaterialConductor, 0.8f, 0.315f, 1.0f}},
      {{gpu::kMaterialDielectric, 0.9f, 0.3f, 1.5f}, {gpu::kMaterialDielectric, 0.9f, 0.3f, 1.45f}},
  };
  for (const Case& c : cases) {
    glm::vec3 wi = glm::normalize(glm::vec3(0.5f, 0.3f, 0.8f));
    SampleIn in{c.sampled, {0, 0, 1, 0}, {wi.x, wi.y, wi.z, 0}, 555u, {}};
    std::vector<SampleOut> out = test::runKernel<SampleOut>("bsdf_sample", std::vector<SampleIn>{in}, kSamples, kSamples);
    std::vector<glm::dvec3> dirs;
    for (const SampleOut& o : out)
      if (o.flags & 1u) dirs.emplace_back(o.wo[0], o.wo[1], o.wo[2]);
    const glm::dvec3 n(0, 0, 1), wid(wi);
    Chi2Result r = test::chi2Sphere(
        dirs, kSamples, [&](const glm::dvec3& w) { return test::bsdfPdfReference(c.claimed, n, wid, w); }, kCosBins,
        kPhiBins, Chi2Options{kFamilyLevel, kChi2Tests, 5.0});
    EXPECT_FALSE(r.passed) << "a wrong density was accepted: " << r.report;
    std::printf("wrong density (type %u): chi2 %.1f dof %d p %.3g\n", c.sampled.type, r.statistic, r.dof, r.pValue);
  }
}

// ---- Warps --------------------------------------------------------------------------------------

struct WarpOut {
  float cosine[3];
  float sphere[3];
  float bary[2];
  float t[3];
  float b[3];
  float pad[2];
};

std::vector<WarpOut> runWarps(uint32_t count, uint32_t seed) {
  std::vector<float> in(4 + 4 * size_t(count), 0.0f);
  std::memcpy(in.data(), &seed, 4);
  for (uint32_t i = 0; i < count; ++i) in[4 + 4 * i + 2] = 1.0f;  // normals: unused here
  return test::runKernel<WarpOut>("bsdf_warp", in, count, count);
}

TEST(Warps, CosineHemisphereAndUniformSphere) {
  std::vector<WarpOut> out = runWarps(kSamples, 77u);
  std::vector<glm::dvec3> cosine, sphere;
  for (const WarpOut& o : out) {
    cosine.emplace_back(o.cosine[0], o.cosine[1], o.cosine[2]);
    sphere.emplace_back(o.sphere[0], o.sphere[1], o.sphere[2]);
  }
  Chi2Options options{kFamilyLevel, kChi2Tests, 5.0};
  Chi2Result rc = test::chi2Sphere(
      cosine, kSamples, [](const glm::dvec3& w) { return std::max(w.z, 0.0) / std::numbers::pi; }, kCosBins, kPhiBins,
      options);
  EXPECT_TRUE(rc.passed) << rc.report;
  Chi2Result rs = test::chi2Sphere(
      sphere, kSamples, [](const glm::dvec3&) { return 0.25 / std::numbers::pi; }, kCosBins, kPhiBins, options);
  EXPECT_TRUE(rs.passed) << rs.report;
  std::printf("cosine hemisphere chi2 %.1f dof %d p %.3f; uniform sphere chi2 %.1f dof %d p %.3f\n", rc.statistic,
              rc.dof, rc.pValue, rs.statistic, rs.dof, rs.pValue);
}

TEST(Warps, TriangleBarycentricsUniformByArea) {
  std::vector<WarpOut> out = runWarps(kSamples, 78u);
  std::vector<glm::dvec2> bary;
  for (const WarpOut& o : out) bary.emplace_back(o.bary[0], o.bary[1]);
  Chi2Options options{kFamilyLevel, kChi2Tests, 5.0};
  test::Grid2D grid{0.0, 1.0, 0.0, 1.0, 32, 32};
  Chi2Result r = test::chi2Test2D(
      grid, bary, kSamples, [](double x, double y) { return x + y <= 1.0 ? 2.0 : 0.0; }, options);
  EXPECT_TRUE(r.passed) << r.report;
  std::printf("triangle barycentrics chi2 %.1f dof %d p %.3f\n", r.statistic, r.dof, r.pValue);
}

}  // namespace
}  // namespace vktg
