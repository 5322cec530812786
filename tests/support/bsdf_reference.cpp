#include "support/bsdf_reference.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace vktg::test {
namespace {

constexpr double kPi = std::numbers::pi;

double alphaOf(const gpu::GpuMaterial& m) { return std::clamp(double(m.roughness), kRefMinAlpha, 1.0); }

// tan^2 of the angle between unit vectors a and b, from the cross product: 1 - cos^2 would lose
// all precision for the nearly aligned normals of a smooth GGX surface.
double tan2Between(const glm::dvec3& a, const glm::dvec3& b) {
  double c = glm::dot(a, b);
  glm::dvec3 x = glm::cross(a, b);
  return glm::dot(x, x) / (c * c);
}

// Microfacet terms of directions given with the (side-adjusted) unit normal nn.
struct Microfacet {
  double alpha;
  glm::dvec3 nn;
  double d(const glm::dvec3& h) const {
    double c = glm::dot(nn, h);
    if (c <= 0.0) return 0.0;
    double a2 = alpha * alpha, k = 1.0 + tan2Between(nn, h) / a2, c2 = c * c;
    return 1.0 / (std::numbers::pi * a2 * c2 * c2 * k * k);
  }
  double lambda(const glm::dvec3& w) const { return 0.5 * (std::sqrt(1.0 + alpha * alpha * tan2Between(nn, w)) - 1.0); }
  double g1(const glm::dvec3& w) const { return 1.0 / (1.0 + lambda(w)); }
  double g2(const glm::dvec3& wi, const glm::dvec3& wo) const { return 1.0 / (1.0 + lambda(wi) + lambda(wo)); }
};

double schlick(double f0, double c) { return f0 + (1.0 - f0) * std::pow(1.0 - std::clamp(c, 0.0, 1.0), 5.0); }

struct Lobe {
  double f = 0.0;
  double pdf = 0.0;
};

// Reflection about the normal `nn` on wi's side; fresnel(cos between wi and h) -> F.
template <class Fresnel>
Lobe reflection(const Microfacet& mf, const glm::dvec3& nn, const glm::dvec3& wi, const glm::dvec3& wo,
                Fresnel fresnel) {
  double ci = glm::dot(nn, wi), co = glm::dot(nn, wo);
  glm::dvec3 h = glm::normalize(wi + wo);
  double f = fresnel(glm::dot(wi, h));
  double d = mf.d(h);
  Lobe l;
  l.f = f * d * mf.g2(wi, wo) / (4.0 * ci * co);
  // pdf_h = D_wi(h) = G1(wi) (wi.h) D(h) / (wi.n); pdf(wo) = pdf_h / (4 wo.h), wo.h = wi.h. The
  // caller multiplies by the probability of choosing reflection.
  l.pdf = mf.g1(wi) * d / (4.0 * ci);
  return l;
}

Lobe refraction(const Microfacet& mf, const glm::dvec3& nn, const glm::dvec3& wi, const glm::dvec3& wo,
                double etaI, double etaO) {
  // Walter 2007 eq. 16, h_t = -(eta_i i + eta_o o) with both vectors pointing away.
  glm::dvec3 ht = -(etaI * wi + etaO * wo);
  double len = glm::length(ht);
  Lobe l;
  if (len < 1e-300) return l;
  ht /= len;
  if (glm::dot(ht, nn) < 0.0) ht = -ht;
  double ih = glm::dot(wi, ht), oh = glm::dot(wo, ht);
  if (ih <= 0.0 || oh >= 0.0) return l;
  double fr = fresnelDielectricReference(ih, etaI, etaO);
  double ci = glm::dot(nn, wi), co = glm::dot(nn, wo);
  double d = mf.d(ht);
  double sq = etaI * ih + etaO * oh;
  sq *= sq;
  // Walter's f_t(i -> o) with light arriving along our wo and leaving toward the camera along wi:
  // the eta^2 in the numerator is the index on the leaving (camera) side, which makes it the
  // radiance BSDF that camera-to-light path tracing needs.
  l.f = std::abs(ih * oh / (ci * co)) * etaI * etaI * (1.0 - fr) * d * mf.g2(wi, wo) / sq;
  double jacobian = etaO * etaO * std::abs(oh) / sq;  // Walter eq. 17
  l.pdf = (1.0 - fr) * mf.g1(wi) * ih * d / ci * jacobian;
  return l;
}

enum class Want { kEval, kPdf };

double evaluate(const gpu::GpuMaterial& m, glm::dvec3 n, glm::dvec3 wi, glm::dvec3 wo, Want want) {
  // Inputs often come from float vectors whose norms are 1 +- 1e-7: normalise so the reference
  // evaluates the directions they stand for.
  n = glm::normalize(n);
  wi = glm::normalize(wi);
  wo = glm::normalize(wo);
  double side = glm::dot(n, wi) >= 0.0 ? 1.0 : -1.0;
  glm::dvec3 nn = side * n;
  double ci = glm::dot(nn, wi), co = glm::dot(nn, wo);
  if (ci < kRefMinCos || std::abs(co) < kRefMinCos) return 0.0;
  if (m.type == gpu::kMaterialDiffuse) {
    if (co <= 0.0) return 0.0;
    return want == Want::kEval ? m.albedo / kPi : co / kPi;
  }
  Microfacet mf{alphaOf(m), nn};
  if (m.type == gpu::kMaterialConductor) {
    if (co <= 0.0) return 0.0;
    Lobe l = reflection(mf, nn, wi, wo, [&](double c) { return schlick(m.albedo, c); });
    return want == Want::kEval ? l.f : l.pdf;
  }
  bool outside = side > 0.0;
  double etaI = outside ? 1.0 : m.ior;
  double etaT = outside ? m.ior : 1.0;
  Lobe l;
  if (co > 0.0) {
    glm::dvec3 h = glm::normalize(wi + wo);
    double fresnel = fresnelDielectricReference(glm::dot(wi, h), etaI, etaT);
    l = reflection(mf, nn, wi, wo, [&](double) { return fresnel; });
    l.pdf *= fresnel;
  } else {
    l = refraction(mf, nn, wi, wo, etaI, etaT);
  }
  return want == Want::kEval ? m.albedo * l.f : l.pdf;
}

}  // namespace

double fresnelDielectricReference(double cosI, double etaI, double etaT) {
  double sinT = etaI / etaT * std::sqrt(std::max(0.0, 1.0 - cosI * cosI));
  if (sinT >= 1.0) return 1.0;
  double cosT = std::sqrt(1.0 - sinT * sinT);
  double perp = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
  double par = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
  return 0.5 * (perp * perp + par * par);
}

double bsdfEvalReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi, const glm::dvec3& wo) {
  return evaluate(m, n, wi, wo, Want::kEval);
}

double bsdfPdfReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi, const glm::dvec3& wo) {
  return evaluate(m, n, wi, wo, Want::kPdf);
}

double bsdfEtaRatioReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi,
                             const glm::dvec3& wo) {
  if (m.type != gpu::kMaterialDielectric) return 1.0;
  bool wiOutside = glm::dot(n, wi) >= 0.0;
  bool woOutside = glm::dot(n, wo) >= 0.0;
  if (wiOutside == woOutside) return 1.0;
  return wiOutside ? m.ior : 1.0 / m.ior;
}

namespace {

// w rotated by `angle` about a random axis orthogonal to it.
glm::dvec3 rotateRandomly(const glm::dvec3& w, double angle, std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  glm::dvec3 axis;
  do {
    axis = glm::cross(w, glm::dvec3(g(rng), g(rng), g(rng)));
  } while (glm::length(axis) < 1e-6);
  axis = glm::normalize(axis);
  return w * std::cos(angle) + glm::cross(axis, w) * std::sin(angle);
}

}  // namespace

double bsdfSensitivityReference(const gpu::GpuMaterial& m, const glm::dvec3& n, const glm::dvec3& wi,
                                const glm::dvec3& wo, bool eval, uint64_t seed) {
  constexpr double kStep = 1e-6;
  std::mt19937_64 rng(seed);
  auto value = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return eval ? bsdfEvalReference(m, a, b, c) : bsdfPdfReference(m, a, b, c);
  };
  double v0 = value(n, wi, wo);
  double kappa = 0.0;
  for (int k = 0; k < 6; ++k) {
    glm::dvec3 a = glm::normalize(n), b = glm::normalize(wi), c = glm::normalize(wo);
    double v = value(rotateRandomly(a, kStep, rng), rotateRandomly(b, kStep, rng), rotateRandomly(c, kStep, rng));
    if ((v == 0.0) != (v0 == 0.0)) return INFINITY;
    if (v0 != 0.0) kappa = std::max(kappa, std::abs(v - v0) / (std::abs(v0) * kStep));
  }
  return kappa;
}

}  // namespace vktg::test
