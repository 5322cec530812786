#include "support/grad_test.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "support/gpu_context.h"
#include "support/test_gates.h"
#include "support/test_scenes.h"

namespace vktg::test {
namespace {

// Above this many degrees of freedom Student's t is the normal distribution for our purposes
// (the quantiles differ by under 1e-5 relative).
constexpr double kNormalDof = 1e7;

PixelEstimate layerEstimate(const ImageSet& mean, const ImageSet& variance, double dof) {
  PixelEstimate e;
  e.mean = mean.layers.at(0).pixels;
  e.variance = variance.layers.at(0).pixels;
  e.dof = dof;
  return e;
}

// Running mean and sum of squared deviations per pixel (Welford), over independent seeds.
struct SeedAccumulator {
  std::vector<double> mean, m2;
  uint32_t count = 0;

  void add(const std::vector<double>& x) {
    if (mean.empty()) {
      mean.assign(x.size(), 0.0);
      m2.assign(x.size(), 0.0);
    }
    ++count;
    for (size_t i = 0; i < x.size(); ++i) {
      double delta = x[i] - mean[i];
      mean[i] += delta / count;
      m2[i] += delta * (x[i] - mean[i]);
    }
  }
  // Mean and the variance of that mean (sample variance / count).
  PixelEstimate estimate() const {
    PixelEstimate e;
    e.dof = double(count) - 1.0;
    for (size_t i = 0; i < mean.size(); ++i) {
      e.mean.push_back(float(mean[i]));
      e.variance.push_back(float(m2[i] / (double(count) - 1.0) / double(count)));
    }
    return e;
  }
};

std::vector<double> asDoubles(const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); }

// Welch-Satterthwaite degrees of freedom of va + vb.
double welchDof(double va, double dofA, double vb, double dofB) {
  double num = (va + vb) * (va + vb);
  double den = (dofA > 0 ? va * va / dofA : 0.0) + (dofB > 0 ? vb * vb / dofB : 0.0);
  return den > 0 ? num / den : kNormalDof * 10;
}

// cos(phi)^(dof - 1) is Student's t density in phi = atan(t / sqrt(dof)); beyond phi = 12 / sqrt(dof - 1)
// it is below exp(-72) of its peak, so the integrals stop there.
double phiCutoff(double dof) { return dof > 1.0 ? std::min(std::numbers::pi / 2, 12.0 / std::sqrt(dof - 1.0)) : std::numbers::pi / 2; }

double cosPowerIntegral(double from, double to, double dof) {
  if (!(to > from)) return 0.0;
  return integrate([dof](double phi) { return std::pow(std::cos(phi), dof - 1.0); }, from, to, 64);
}

}  // namespace

GradientImages gradientInTest(const Scene& scene, const std::vector<std::string>& parameters, const RenderOptions& options) {
  GradientOptions gradient;
  gradient.render = options;
  gradient.interior = true;
  gradient.pathLength = false;
  gradient.edges = false;  // the interior scenes have no visibility boundary a gated path sees
  gradient.antithetic = AntitheticMode::Off;
  GradientResult r = renderGradient(testRenderer(), scene, parameters, gradient);
  // Each pixel's variance is the sample variance of its spp samples.
  double dof = double(scene.render.spp) - 1.0;
  GradientImages images;
  for (size_t k = 0; k < parameters.size(); ++k)
    images.derivatives.push_back(layerEstimate(r.interior.derivatives.at(k), r.interior.variances.at(k), dof));
  images.primal = layerEstimate(r.primal.mean, r.primal.variance, dof);
  images.nonFinite = r.stats.nonFinite;
  images.seconds = r.stats.seconds;
  return images;
}

FiniteDifferenceImages finiteDifferenceInTest(const Scene& scene, const std::string& parameter, double eps,
                                              uint32_t seeds, const RenderOptions& options, PixelEstimate* halfStep) {
  SeedAccumulator full, half;
  FiniteDifferenceImages result;
  for (uint32_t k = 0; k < seeds; ++k) {
    Scene seeded = scene;
    seeded.render.seed = scene.render.seed + k + 1;
    FiniteDifferenceResult fd = finiteDifference(testRenderer(), seeded, parameter, eps, options);
    result.seconds += fd.stats.seconds;
    result.nonFinite += fd.stats.nonFinite;
    std::vector<double> d = asDoubles(fd.derivative.layers.at(0).pixels);
    full.add(d);
    if (halfStep) {
      FiniteDifferenceResult h = finiteDifference(testRenderer(), seeded, parameter, 0.5 * eps, options);
      result.seconds += h.stats.seconds;
      result.nonFinite += h.stats.nonFinite;
      std::vector<double> diff = asDoubles(h.derivative.layers.at(0).pixels);
      for (size_t i = 0; i < diff.size(); ++i) diff[i] = d[i] - diff[i];
      half.add(diff);
    }
  }
  result.derivative = full.estimate();
  if (halfStep) *halfStep = half.estimate();
  return result;
}

double studentTwoSidedTail(double t, double dof) {
  t = std::abs(t);
  if (dof > kNormalDof) return std::erfc(t / std::sqrt(2.0));
  double cut = phiCutoff(dof);
  double phi = std::atan(t / std::sqrt(dof));
  return cosPowerIntegral(phi, cut, dof) / cosPowerIntegral(0.0, cut, dof);
}

double studentTwoSidedQuantile(double tail, double dof) {
  if (dof > kNormalDof) {
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
      double mid = 0.5 * (lo + hi);
      if (std::erfc(mid / std::sqrt(2.0)) > tail) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi);
  }
  // Bisection in phi = atan(t / sqrt(dof)): the tail falls monotonically from 1 at phi = 0.
  double cut = phiCutoff(dof), total = cosPowerIntegral(0.0, cut, dof);
  double lo = 0, hi = cut;
  for (int i = 0; i < 100; ++i) {
    double mid = 0.5 * (lo + hi);
    if (cosPowerIntegral(mid, cut, dof) / total > tail) lo = mid; else hi = mid;
  }
  return std::sqrt(dof) * std::tan(0.5 * (lo + hi));
}

namespace {

Comparison compare(const PixelEstimate& a, const std::vector<double>& b, const std::vector<float>* bVariance, double bDof,
                   double alpha) {
  Comparison c;
  size_t n = a.mean.size();
  // Sidak: per-pixel level so that the chance of any false rejection over the image is alpha.
  double perTest = 1.0 - std::pow(1.0 - alpha, 1.0 / double(std::max<size_t>(n, 1)));
  double worstRatio = -1;
  for (size_t i = 0; i < n; ++i) {
    double va = a.variance[i], vb = bVariance ? double((*bVariance)[i]) : 0.0;
    bool aBlind = a.mean[i] == 0.0f && va == 0.0, bBlind = bVariance && b[i] == 0.0 && vb == 0.0;
    if (aBlind != bBlind && (aBlind ? vb : va) > 0.0) {
      c.untestable++;
      continue;
    }
    c.tested++;
    double diff = double(a.mean[i]) - b[i], variance = va + vb;
    double dof = welchDof(va, a.dof, vb, bVariance ? bDof : 0.0);
    double threshold = studentTwoSidedQuantile(perTest, dof);
    double t = variance > 0 ? std::abs(diff) / std::sqrt(variance) : (diff == 0 ? 0.0 : INFINITY);
    if (t > threshold) c.rejected++;
    if (t / threshold > worstRatio) {
      worstRatio = t / threshold;
      c.worstT = t;
      std::ostringstream text;
      text << "pixel " << i << ": " << a.mean[i] << " vs " << b[i] << " (t = " << t << ", threshold " << threshold
           << " at " << dof << " dof, se " << std::sqrt(va) << " and " << std::sqrt(vb) << ")";
      c.worst = text.str();
    }
  }
  return c;
}

}  // namespace

Comparison compareEstimates(const PixelEstimate& a, const PixelEstimate& b, double alpha) {
  return compare(a, asDoubles(b.mean), &b.variance, b.dof, alpha);
}

Comparison compareWithExact(const PixelEstimate& a, const std::vector<double>& exact, double alpha) {
  return compare(a, exact, nullptr, 0.0, alpha);
}

PixelEstimate imageSum(const PixelEstimate& e) {
  double mean = 0, variance = 0;
  for (size_t i = 0; i < e.mean.size(); ++i) mean += e.mean[i], variance += e.variance[i];
  return PixelEstimate{{float(mean)}, {float(variance)}, e.dof};
}

double signalToNoise(const PixelEstimate& e) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < e.mean.size(); ++i)
    if (e.variance[i] > 0) {
      sum += std::abs(e.mean[i]) / std::sqrt(double(e.variance[i]));
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

// ----------------------------------------------------------------------------------------------
// Confocal plane.

ConfocalReference confocalReference() {
  double hi = kConfocalMu + kGaussianCutoff * kConfocalSigma;
  double rMax = std::sqrt(0.25 * hi * hi - kConfocalHeight * kConfocalHeight);
  auto term = [](double r, int which) {
    double d = std::sqrt(r * r + kConfocalHeight * kConfocalHeight), len = 2 * d;
    double f = kConfocalRho * kConfocalIntensity * kConfocalHeight * kConfocalHeight * kConfocalHeight / (std::numbers::pi * std::pow(d, 7));
    double w = gaussianWeight(len, kConfocalMu, kConfocalSigma), wPrime = -(len - kConfocalMu) / (kConfocalSigma * kConfocalSigma) * w;
    double dLight = f * (1 / kConfocalHeight - 3 * kConfocalHeight / (d * d)) * w + f * wPrime * kConfocalHeight / d;
    double dSensor = f * (2 / kConfocalHeight - 4 * kConfocalHeight / (d * d)) * w + f * wPrime * kConfocalHeight / d;
    double value = which == 0 ? f * w : which == 1 ? dLight + dSensor : which == 2 ? dLight : -f * wPrime;
    return 2 * std::numbers::pi * r * value;
  };
  ConfocalReference ref;
  ref.m = integrate([&](double r) { return term(r, 0); }, 0, rMax, 256);
  ref.dPlane = integrate([&](double r) { return term(r, 1); }, 0, rMax, 256);
  ref.dLight = integrate([&](double r) { return term(r, 2); }, 0, rMax, 256);
  ref.dGate = integrate([&](double r) { return term(r, 3); }, 0, rMax, 256);
  return ref;
}

namespace {

// Finite differences are measured over this many independent seeds.
constexpr uint32_t kSeeds = 16;

Scene confocalScene(uint32_t spp, uint32_t seed) {
  Scene scene = confocalPlaneScene(kConfocalHeight, 3.0, 3.0, kConfocalRho, kConfocalIntensity);
  scene.gate = gaussianGate(kConfocalMu, kConfocalSigma);
  scene.render.spp = spp;
  scene.render.seed = seed;
  Parameter p;
  p = {};
  p.name = "albedo", p.kind = ParameterKind::Albedo, p.target = "plane";
  scene.parameters.push_back(p);
  p = {};
  p.name = "intensity", p.kind = ParameterKind::Intensity, p.target = "light";
  scene.parameters.push_back(p);
  p = {};
  // The plane moves away from sensor and light: h grows.
  p.name = "plane_h", p.kind = ParameterKind::Translate, p.target = "plane", p.axis = {0.0f, 0.0f, -1.0f};
  scene.parameters.push_back(p);
  p = {};
  p.name = "light_z", p.kind = ParameterKind::LightPosition, p.target = "light", p.axis = {0.0f, 0.0f, 1.0f};
  scene.parameters.push_back(p);
  p = {};
  p.name = "gate_mu", p.kind = ParameterKind::GateCenter;
  scene.parameters.push_back(p);
  return scene;
}

const std::vector<std::string> kConfocalParameters = {"albedo", "intensity", "plane_h", "light_z", "gate_mu"};

// Steps: albedo and intensity enter linearly (any step is exact); the geometric ones and the gate
// centre change path lengths by at most 2 eps = 0.1 sigma.
const std::map<std::string, double> kConfocalEps = {
    {"albedo", 0.05}, {"intensity", 0.1}, {"plane_h", 0.005}, {"light_z", 0.005}, {"gate_mu", 0.005}};

// FD(eps) - FD(eps/2) (same seeds) estimates 3/4 of FD(eps)'s truncation error b. The check
// rejects the hypothesis |b| <= se/4 (se: the comparison's standard error) when 4/3 |mean| exceeds
// se/4 by more than the Sidak-corrected t quantile of its own noise. A bias of se/4 changes a
// two-sided test at |t| ~ 4 by under a factor 3 in its false-rejection probability (level 1e-4).
// The difference's noise is not always small: where the renderer makes discrete choices from the
// parameter (light selection by power, Russian roulette), common random numbers decorrelate.
void expectTruncationNegligible(const std::string& label, const PixelEstimate& halfStep, const PixelEstimate& fd,
                                const PixelEstimate& gradient) {
  size_t n = halfStep.mean.size();
  double perTest = 1.0 - std::pow(1.0 - kGradAlpha, 1.0 / double(n));
  double q = studentTwoSidedQuantile(perTest, halfStep.dof);
  double worstExcess = -INFINITY, worstRatio = 0;
  size_t worst = 0;
  for (size_t i = 0; i < n; ++i) {
    double comparison = std::sqrt(double(fd.variance[i]) + double(gradient.variance[i]));
    double truncation = 4.0 / 3.0 * std::abs(double(halfStep.mean[i]));
    double noise = 4.0 / 3.0 * std::sqrt(double(halfStep.variance[i]));
    double excess = truncation - 0.25 * comparison - q * noise;
    if (excess > worstExcess) worstExcess = excess, worst = i;
    if (comparison > 0) worstRatio = std::max(worstRatio, truncation / comparison);
  }
  EXPECT_LE(worstExcess, 0.0) << label << ": finite-difference truncation error exceeds a quarter of the comparison's "
                              << "standard error at pixel " << worst << ": FD(eps) - FD(eps/2) = "
                              << halfStep.mean[worst] << " (se " << std::sqrt(halfStep.variance[worst]) << ")";
  std::printf("  %-10s eps check: estimated truncation / comparison se at most %.3f\n", label.c_str(), worstRatio);
}

struct ConfocalFd {
  std::map<std::string, PixelEstimate> derivative;
};

// Finite differences of the confocal scene, shared by the three NEE tests: the primal's
// expectation does not depend on the estimator, so one reference (standard NEE: every sample is a
// smooth function of the parameters, which common random numbers exploit) serves all three.
const ConfocalFd& confocalFd(uint32_t fdSpp) {
  static ConfocalFd fd;
  if (!fd.derivative.empty()) return fd;
  Scene scene = confocalScene(fdSpp, 700);
  RenderOptions options;
  options.nee = NeeMode::Standard;
  for (const std::string& name : kConfocalParameters) {
    PixelEstimate halfStep;
    FiniteDifferenceImages r = finiteDifferenceInTest(scene, name, kConfocalEps.at(name), kSeeds, options, &halfStep);
    EXPECT_EQ(r.nonFinite, 0u) << name;
    fd.derivative[name] = r.derivative;
    fd.derivative[name + "/half"] = halfStep;
    std::printf("  fd %-10s %.6g (se %.3g, %.2f s)\n", name.c_str(), r.derivative.mean[0],
                std::sqrt(r.derivative.variance[0]), r.seconds);
  }
  return fd;
}

}  // namespace

void checkConfocal(NeeMode nee, uint32_t spp, uint32_t seed, uint32_t fdSpp) {
  ConfocalReference ref = confocalReference();
  const std::map<std::string, double> exact = {{"albedo", ref.m / kConfocalRho},
                                               {"intensity", ref.m / kConfocalIntensity},
                                               {"plane_h", ref.dPlane},
                                               {"light_z", ref.dLight},
                                               {"gate_mu", ref.dGate}};
  RenderOptions options;
  options.nee = nee;
  GradientImages g = gradientInTest(confocalScene(spp, seed), kConfocalParameters, options);
  EXPECT_EQ(g.nonFinite, 0u);
  std::printf("  gradient (%s nee, %u spp): %.2f s\n", neeModeName(nee), spp, g.seconds);
  Comparison primal = compareWithExact(g.primal, {ref.m}, kGradAlpha);
  EXPECT_EQ(primal.rejected, 0u) << "primal image: " << primal.worst;
  const ConfocalFd& fd = confocalFd(fdSpp);
  for (size_t k = 0; k < kConfocalParameters.size(); ++k) {
    const std::string& name = kConfocalParameters[k];
    const PixelEstimate& d = g.derivatives[k];
    ASSERT_EQ(d.mean.size(), 1u);
    EXPECT_GT(d.variance[0], 0.0f) << name << ": a Monte Carlo estimate with zero variance cannot be tested";
    Comparison a = compareWithExact(d, {exact.at(name)}, kGradAlpha);
    EXPECT_EQ(a.rejected, 0u) << name << " vs exact derivative: " << a.worst;
    const PixelEstimate& f = fd.derivative.at(name);
    Comparison c = compareEstimates(d, f, kGradAlpha);
    EXPECT_EQ(c.rejected, 0u) << name << " vs finite difference: " << c.worst;
    std::printf("  %-10s gradient %.6g (se %.3g), exact %.6g, fd %.6g (se %.3g)\n", name.c_str(), d.mean[0],
                std::sqrt(d.variance[0]), exact.at(name), f.mean[0], std::sqrt(f.variance[0]));
    expectTruncationNegligible(name, fd.derivative.at(name + "/half"), f, d);
  }
}




// ----------------------------------------------------------------------------------------------
// Perspective plane.

namespace {

Scene litPlaneScene(MaterialType type, uint32_t spp, uint32_t seed) {
  Scene scene;
  Material plane;
  plane.name = "plane";
  plane.type = type;
  plane.albedo = 0.7f;
  plane.roughness = 0.3f;
  plane.ior = 1.5f;
  Material lampMaterial;
  lampMaterial.name = "lamp";
  lampMaterial.type = MaterialType::Diffuse;
  lampMaterial.albedo = 0.5f;
  scene.materials = {plane, lampMaterial};
  Shape ground;
  ground.name = "plane";
  ground.material = 0;
  addQuad(ground, {-4.0f, -4.0f, 0.0f}, {4.0f, -4.0f, 0.0f}, {4.0f, 4.0f, 0.0f}, {-4.0f, 4.0f, 0.0f});  // faces +z
  Shape lamp;
  lamp.name = "lamp";
  lamp.material = 1;
  lamp.emission = 5.0f;
  // At z = 1.5, x in [0.9, 1.4], facing down (-z). The camera (z = 2, 30 degrees) sees |x| < 0.14
  // at that height; the point light (z = 1.2) lies below it.
  addQuad(lamp, {0.9f, -0.25f, 1.5f}, {0.9f, 0.25f, 1.5f}, {1.4f, 0.25f, 1.5f}, {1.4f, -0.25f, 1.5f});
  scene.shapes = {ground, lamp};
  scene.pointLights.push_back({"point", {-0.9f, 0.3f, 1.2f}, 2.0f});
  scene.camera = pinholeCamera({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 30.0f, 12);
  // Paths reaching the plane's edge (4 m out) are longer than the support's end, 7.25 m.
  scene.gate = gaussianGate(4.0, 0.5);
  scene.render.spp = spp;
  scene.render.seed = seed;
  scene.render.maxDepth = 4;
  Parameter p;
  p.name = "albedo", p.kind = ParameterKind::Albedo, p.target = "plane";
  if (type != MaterialType::Dielectric) scene.parameters.push_back(p);
  p = {};
  p.name = "emission", p.kind = ParameterKind::Emission, p.target = "lamp";
  scene.parameters.push_back(p);
  p = {};
  p.name = "plane_z", p.kind = ParameterKind::Translate, p.target = "plane", p.axis = {0.0f, 0.0f, 1.0f};
  scene.parameters.push_back(p);
  p = {};
  p.name = "light_x", p.kind = ParameterKind::LightPosition, p.target = "point", p.axis = {1.0f, 0.0f, 0.0f};
  scene.parameters.push_back(p);
  if (type != MaterialType::Diffuse) {
    p = {};
    p.name = "roughness", p.kind = ParameterKind::Roughness, p.target = "plane";
    scene.parameters.push_back(p);
  }
  if (type == MaterialType::Dielectric) {
    p = {};
    p.name = "ior", p.kind = ParameterKind::Ior, p.target = "plane";
    scene.parameters.push_back(p);
  }
  return scene;
}

const std::map<std::string, double> kPlaneEps = {{"albedo", 0.02}, {"emission", 0.5}, {"plane_z", 0.02},
                                                 {"light_x", 0.01}, {"roughness", 0.01}, {"ior", 0.02}};

}  // namespace

void checkLitPlane(MaterialType type, const std::vector<std::string>& parameters, uint32_t spp, uint32_t fdSpp) {
  RenderOptions options;
  options.nee = NeeMode::Standard;
  Scene scene = litPlaneScene(type, spp, 31 + uint32_t(type));
  GradientImages g = gradientInTest(scene, parameters, options);
  EXPECT_EQ(g.nonFinite, 0u);
  std::printf("  gradient (%u spp): %.2f s\n", spp, g.seconds);
  Scene fdScene = litPlaneScene(type, fdSpp, 900 + 100 * uint32_t(type));
  for (size_t k = 0; k < parameters.size(); ++k) {
    const std::string& name = parameters[k];
    PixelEstimate halfStep;
    FiniteDifferenceImages fd = finiteDifferenceInTest(fdScene, name, kPlaneEps.at(name), kSeeds, options, &halfStep);
    EXPECT_EQ(fd.nonFinite, 0u) << name;
    const PixelEstimate& d = g.derivatives[k];
    Comparison c = compareEstimates(d, fd.derivative, kGradAlpha);
    EXPECT_EQ(c.untestable, 0u) << name;
    EXPECT_EQ(c.rejected, 0u) << name << " vs finite difference: " << c.rejected << " of " << c.tested
                              << " pixels rejected; worst " << c.worst;
    // The comparison must be able to see the derivative at all.
    EXPECT_GT(signalToNoise(d), 5.0) << name;
    std::printf("  %-10s gradient snr %.1f, fd snr %.1f, worst |t| %.2f (fd %.2f s)\n", name.c_str(),
                signalToNoise(d), signalToNoise(fd.derivative), c.worstT, fd.seconds);
    expectTruncationNegligible(name, halfStep, fd.derivative, d);
    const PixelEstimate sum = imageSum(d), fdSum = imageSum(fd.derivative);
    Comparison s = compareEstimates(sum, fdSum, kGradAlpha);
    EXPECT_EQ(s.rejected, 0u) << name << " image sum vs finite difference: " << s.worst;
    std::printf("  %-10s image sum %.5g vs fd %.5g: %s\n", name.c_str(), sum.mean[0], fdSum.mean[0], s.worst.c_str());
    expectTruncationNegligible(name + " sum", imageSum(halfStep), fdSum, sum);
  }
}




ImageSet randomAdjointImage(uint32_t width, uint32_t height, uint32_t layers, uint32_t seed) {
  ImageSet a;
  a.width = width;
  a.height = height;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (uint32_t l = 0; l < layers; ++l) {
    ImageLayer layer;
    for (uint32_t i = 0; i < width * height; ++i) layer.pixels.push_back(u(rng));
    a.layers.push_back(layer);
  }
  return a;
}

}  // namespace vktg::test
