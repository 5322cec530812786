// bsdfEval / bsdfPdf (shaders/lib/bsdf.glsl) against the double-precision twin
// (tests/support/bsdf_reference.cpp) on random configurations, reciprocity, energy, and the
// orthonormal basis of shaders/lib/warp.glsl.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "support/bsdf_reference.h"
#include "support/gpu_test.h"

namespace vktg {
namespace {

// Float bounds come from test::bsdfFloatTolerance (tests/support/bsdf_reference.h). Where the
// bound exceeds kMaxTolerance (sharp GGX peaks at alpha ~ 1e-3; discontinuities such as the
// critical angle or the horizon, where kappa is infinite) the comparison would prove nothing:
// those configurations are counted as excluded and reported.
constexpr double kMaxTolerance = 1e-2;

struct EvalIn {
  gpu::GpuMaterial material;
  float n[4], wi[4], wo[4];
};
struct EvalOut {
  float f, pdf;
};

glm::vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    glm::vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

// Rotates w by a random angle of scale `angle` about a random axis (perturbation near a lobe).
glm::dvec3 perturb(const glm::dvec3& w, double angle, std::mt19937_64& rng) {
  glm::dvec3 axis = glm::normalize(glm::cross(w, glm::dvec3(randomUnit(rng))));
  std::normal_distribution<double> g;
  double a = angle * g(rng);
  return w * std::cos(a) + glm::cross(axis, w) * std::sin(a) + axis * glm::dot(axis, w) * (1 - std::cos(a));
}

EvalIn makeIn(const gpu::GpuMaterial& m, glm::vec3 n, glm::vec3 wi, glm::vec3 wo) {
  return {m, {n.x, n.y, n.z, 0}, {wi.x, wi.y, wi.z, 0}, {wo.x, wo.y, wo.z, 0}};
}

glm::dvec3 dv(const float* p) { return {p[0], p[1], p[2]}; }

// Random configurations that cover the lobes: a third of wo uniform, the rest near the mirror
// or refracted direction, where microfacet BSDFs take their large values.
std::vector<EvalIn> randomConfigurations(size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<EvalIn> out;
  for (size_t i = 0; i < count; ++i) {
    gpu::GpuMaterial m;
    m.type = uint32_t(i % 3);
    m.albedo = float(0.05 + 0.95 * uni(rng));
    m.roughness = float(std::pow(10.0, -3.0 * uni(rng)));
    m.ior = float(1.1 + 1.3 * uni(rng));
    glm::vec3 n = randomUnit(rng), wi = randomUnit(rng);
    glm::dvec3 nd(n), wid(wi);
    glm::dvec3 side = glm::dot(nd, wid) >= 0 ? nd : -nd;
    glm::dvec3 wo;
    int mode = int(uni(rng) * 3);
    if (mode == 0) {
      wo = glm::dvec3(randomUnit(rng));
    } else {
      glm::dvec3 mirror = 2 * glm::dot(side, wid) * side - wid;
      glm::dvec3 target = mirror;
      if (mode == 2 && m.type == gpu::kMaterialDielectric) {
        double eta = glm::dot(nd, wid) >= 0 ? m.ior : 1.0 / m.ior;
        glm::dvec3 r = glm::refract(-wid, side, 1.0 / eta);
        if (glm::length(r) > 0.5) target = r;
      }
      wo = perturb(target, 2.0 * m.roughness, rng);
    }
    out.push_back(makeIn(m, n, wi, glm::vec3(glm::normalize(wo))));
  }
  return out;
}

struct Agreement {
  size_t compared = 0, nonzero = 0, failed = 0, illConditioned = 0;
  double worst = 0.0;       // worst relative error
  double worstUlps = 0.0;   // worst relative error in units of eps * kappa (ill-conditioned part)
  std::vector<std::string> failures;
};

void compare(Agreement& a, double gpu, double ref, double kappa, const std::string& what) {
  if (!std::isfinite(gpu)) {
    ++a.failed;
    a.failures.push_back(what + ": not finite");
    return;
  }
  double allowed = test::bsdfFloatTolerance(kappa);
  if (!(allowed <= kMaxTolerance)) {
    ++a.illConditioned;
    return;
  }
  ++a.compared;
  // Values below float's normal range cannot carry a relative bound.
  if (std::abs(ref) < 1e-30) {
    if (std::abs(gpu) > 1e-29) {
      ++a.failed;
      a.failures.push_back(what + ": expected 0, got " + std::to_string(gpu));
    }
    return;
  }
  ++a.nonzero;
  double e = std::abs(gpu - ref) / std::abs(ref);
  a.worst = std::max(a.worst, e);
  if (e > test::kBsdfRelTolerance) a.worstUlps = std::max(a.worstUlps, e / (test::kFloatEps * kappa));
  if (e > allowed) {
    ++a.failed;
    if (a.failures.size() < 10) {
      char buf[160];
      std::snprintf(buf, sizeof buf, ": gpu %.9g reference %.9g, allowed relative error %.3g", gpu, ref, allowed);
      a.failures.push_back(what + buf);
    }
  }
}

std::string describe(const EvalIn& e) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "type %u albedo %.3f alpha %.4g ior %.3f cos(n,wi) %.4f cos(n,wo) %.4f",
                e.material.type, e.material.albedo, e.material.roughness, e.material.ior,
                glm::dot(dv(e.n), dv(e.wi)), glm::dot(dv(e.n), dv(e.wo)));
  return buf;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "  " + l + "\n";
  return s;
}

void printAgreement(const char* name, const Agreement& a) {
  std::printf("%s: %zu compared (%zu non-zero), worst relative error %.2e (worst excess %.1f eps*kappa), %zu "
              "excluded as ill-conditioned\n",
              name, a.compared, a.nonzero, a.worst, a.worstUlps, a.illConditioned);
}

TEST(BsdfGpu, EvalAndPdfMatchDoublePrecisionTwin) {
  std::vector<EvalIn> in = randomConfigurations(6000, 42);
  std::vector<EvalOut> out = test::runKernel<EvalOut>("bsdf_eval", in, in.size(), uint32_t(in.size()));
  Agreement evalA, pdfA;
  size_t grazing = 0;
  for (size_t i = 0; i < in.size(); ++i) {
    const gpu::GpuMaterial& m = in[i].material;
    glm::dvec3 n = dv(in[i].n), wi = dv(in[i].wi), wo = dv(in[i].wo);
    // Within a few ulps of the kBsdfMinCos cut the two sides may legitimately disagree.
    if (std::abs(glm::dot(n, wi)) < 2 * test::kRefMinCos || std::abs(glm::dot(n, wo)) < 2 * test::kRefMinCos) {
      ++grazing;
      continue;
    }
    double f = test::bsdfEvalReference(m, n, wi, wo), p = test::bsdfPdfReference(m, n, wi, wo);
    compare(evalA, out[i].f, f, test::bsdfSensitivityReference(m, n, wi, wo, true, i), "eval " + describe(in[i]));
    compare(pdfA, out[i].pdf, p, test::bsdfSensitivityReference(m, n, wi, wo, false, i), "pdf " + describe(in[i]));
  }
  printAgreement("eval", evalA);
  printAgreement("pdf", pdfA);
  std::printf("excluded within 2 kBsdfMinCos of a tangent plane: %zu of %zu\n", grazing, in.size());
  EXPECT_EQ(evalA.failed, 0u) << joined(evalA.failures);
  EXPECT_EQ(pdfA.failed, 0u) << joined(pdfA.failures);
  // The exclusions must stay the exception, or the test would prove little.
  EXPECT_GT(evalA.nonzero, in.size() / 2);
  // At most a tenth of the 2 * in.size() comparisons (roughness is log-uniform down to 1e-3, where
  // the lobe is too sharp for a float bound) may be excluded.
  EXPECT_LT(evalA.illConditioned + pdfA.illConditioned, 2 * in.size() / 10);
}

TEST(BsdfGpu, Reciprocity) {
  std::vector<EvalIn> in = randomConfigurations(3000, 43);
  std::vector<EvalIn> swapped = in;
  for (EvalIn& e : swapped) std::swap(e.wi, e.wo);
  std::vector<EvalOut> a = test::runKernel<EvalOut>("bsdf_eval", in, in.size(), uint32_t(in.size()));
  std::vector<EvalOut> b = test::runKernel<EvalOut>("bsdf_eval", swapped, in.size(), uint32_t(in.size()));
  Agreement reflect, refract;
  for (size_t i = 0; i < in.size(); ++i) {
    const gpu::GpuMaterial& m = in[i].material;
    glm::dvec3 n = dv(in[i].n), wi = dv(in[i].wi), wo = dv(in[i].wo);
    if (std::abs(glm::dot(n, wi)) < 2 * test::kRefMinCos || std::abs(glm::dot(n, wo)) < 2 * test::kRefMinCos) continue;
    // Each GPU value is within bsdfFloatTolerance of its exact value, with its own argument
    // order's sensitivity (for refraction the two orders are conditioned differently), so they
    // differ by at most the sum: compare() allows bsdfFloatTolerance(kappa), and
    // tol(ka) + tol(kb) = tol(ka + kb) + kBsdfRelTolerance <= tol(ka + kb + kBsdfRelTolerance / (128 eps)).
    double kappaA = test::bsdfSensitivityReference(m, n, wi, wo, true, i);
    double kappaB = test::bsdfSensitivityReference(m, n, wo, wi, true, i + in.size());
    double kappa = kappaA + kappaB + test::kBsdfRelTolerance / (test::kBsdfAmplifiedUlps * test::kFloatEps);
    // f(wo, wi) = (eta_wo / eta_wi)^2 f(wi, wo): 1 for reflection.
    double ratio = test::bsdfEtaRatioReference(m, n, wi, wo);
    bool refraction = ratio != 1.0;
    compare(refraction ? refract : reflect, double(b[i].f), double(a[i].f) * ratio * ratio, kappa, describe(in[i]));
  }
  printAgreement("reciprocity, reflection", reflect);
  printAgreement("reciprocity, refraction", refract);
  EXPECT_EQ(reflect.failed, 0u) << joined(reflect.failures);
  EXPECT_EQ(refract.failed, 0u) << joined(refract.failures);
  EXPECT_GT(reflect.nonzero, 1000u);
  EXPECT_GT(refract.nonzero, 100u);
}

// White furnace: a Lambertian surface of albedo 1 reflects all it receives. Monte Carlo over
// uniform directions (so bsdfEval, not the sampler, is what is integrated); 5 standard errors.
TEST(BsdfGpu, WhiteFurnaceDiffuse) {
  std::mt19937_64 rng(44);
  gpu::GpuMaterial m{gpu::kMaterialDiffuse, 1.0f, 0.5f, 1.0f};
  glm::vec3 n = randomUnit(rng), wi = randomUnit(rng);
  std::vector<EvalIn> in;
  constexpr size_t kCount = 1u << 18;
  for (size_t i = 0; i < kCount; ++i) in.push_back(makeIn(m, n, wi, randomUnit(rng)));
  std::vector<EvalOut> out = test::runKernel<EvalOut>("bsdf_eval", in, in.size(), uint32_t(in.size()));
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < kCount; ++i) {
    double v = out[i].f * std::abs(glm::dot(dv(in[i].n), dv(in[i].wo))) * 4 * std::numbers::pi;
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / kCount;
  double se = std::sqrt((sum2 / kCount - mean * mean) / (kCount - 1));
  std::printf("white furnace: %.5f +- %.5f\n", mean, se);
  EXPECT_NEAR(mean, 1.0, 5 * se);
}

struct SampleIn {
  gpu::GpuMaterial material;
  float n[4], wi[4];
  uint32_t seed, pad[3];
};
struct SampleOut {
  float wo[3], weight, pdf;
  uint32_t flags;
  float eval, evalPdf;
};

// Energy: with a white conductor (F0 = 1) or a clear dielectric, the expected sample weight is the
// directional albedo, at most 1 (microfacet single scattering loses energy, never gains it). For
// refraction the radiance scaling 1/eta^2 is undone first. The diffuse weight is exactly albedo.
TEST(BsdfGpu, SampledEnergyAtMostOne) {
  constexpr uint32_t kCount = 1u << 16;
  std::mt19937_64 rng(45);
  for (uint32_t type : {gpu::kMaterialDiffuse, gpu::kMaterialConductor, gpu::kMaterialDielectric})
    for (float alpha : {1e-3f, 0.1f, 1.0f})
      for (float cosWi : {1.0f, 0.3f, 0.01f, -0.5f}) {
        gpu::GpuMaterial m{type, 1.0f, alpha, 1.5f};
        float s = std::sqrt(1 - cosWi * cosWi);
        glm::vec3 wi = glm::normalize(glm::vec3(s * 0.6f, s * 0.8f, cosWi));
        SampleIn in{m, {0, 0, 1, 0}, {wi.x, wi.y, wi.z, 0}, 99u, {}};
        std::vector<SampleOut> out = test::runKernel<SampleOut>("bsdf_sample", std::vector<SampleIn>{in}, kCount, kCount);
        double sum = 0, sum2 = 0;
        size_t nonFinite = 0;
        for (const SampleOut& o : out) {
          if (!std::isfinite(o.weight) || !std::isfinite(o.pdf)) ++nonFinite;
          if (!(o.flags & 1u)) continue;
          double v = o.weight;
          if (o.flags & 2u) {
            double eta = wi.z >= 0 ? m.ior : 1.0 / m.ior;
            v *= eta * eta;
          }
          if (type == gpu::kMaterialDiffuse) {
            EXPECT_EQ(o.weight, 1.0f);
          }
          sum += v;
          sum2 += v * v;
        }
        double mean = sum / kCount;
        double se = std::sqrt(std::max(0.0, sum2 / kCount - mean * mean) / (kCount - 1));
        EXPECT_EQ(nonFinite, 0u);
        EXPECT_LE(mean, 1.0 + 5 * se + 1e-6) << "type " << type << " alpha " << alpha << " cos " << cosWi;
        if (type == gpu::kMaterialDiffuse) {
          EXPECT_EQ(mean, 1.0);
        }
        // A smooth surface at normal incidence loses almost nothing: check the estimate is not trivially small.
        if (type != gpu::kMaterialDiffuse && alpha < 0.01f && cosWi == 1.0f) {
          EXPECT_NEAR(mean, 1.0, 1e-3 + 5 * se);
        }
      }
}

struct WarpOut {
  float cosine[3], sphere[3], bary[2], t[3], b[3], pad[2];
};

TEST(Warps, BasisFromNormalIsOrthonormalAndRightHanded) {
  std::mt19937_64 rng(46);
  std::vector<glm::vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}};
  // Near the poles, where the construction divides by (1 +- n.z).
  for (float e : {1e-3f, 1e-5f, 1e-7f}) {
    normals.push_back(glm::normalize(glm::vec3(e, -e, 1)));
    normals.push_back(glm::normalize(glm::vec3(-e, e, -1)));
  }
  while (normals.size() < 4096) normals.push_back(randomUnit(rng));
  std::vector<float> in(4 + 4 * normals.size(), 0.0f);
  for (size_t i = 0; i < normals.size(); ++i) std::memcpy(&in[4 + 4 * i], &normals[i], 12);
  std::vector<WarpOut> out =
      test::runKernel<WarpOut>("bsdf_warp", in, normals.size(), uint32_t(normals.size()));
  double worst = 0;
  for (size_t i = 0; i < normals.size(); ++i) {
    glm::dvec3 n(normals[i]), t = dv(out[i].t), b = dv(out[i].b);
    double e = std::max({std::abs(glm::length(t) - 1), std::abs(glm::length(b) - 1), std::abs(glm::dot(t, b)),
                         std::abs(glm::dot(t, n)), std::abs(glm::dot(b, n)), glm::length(glm::cross(t, b) - n)});
    worst = std::max(worst, e);
    // Cosine-hemisphere and sphere samples are unit vectors; barycentrics lie in the triangle.
    glm::dvec3 c = dv(out[i].cosine), s = dv(out[i].sphere);
    EXPECT_NEAR(glm::length(c), 1.0, 1e-5);
    EXPECT_GE(c.z, 0.0);
    EXPECT_NEAR(glm::length(s), 1.0, 1e-5);
    EXPECT_GE(out[i].bary[0], 0.0f);
    EXPECT_GE(out[i].bary[1], 0.0f);
    EXPECT_LE(out[i].bary[0] + out[i].bary[1], 1.0f + 1e-6f);
  }
  // A few float roundings of unit-sized quantities.
  EXPECT_LT(worst, 1e-6) << "worst deviation from an orthonormal right-handed frame";
}

}  // namespace
}  // namespace vktg
