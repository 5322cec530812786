#include "support/render_test.h"

#include <cmath>
#include <memory>
#include <sstream>

#include "support/gpu_context.h"

namespace vktg::test {
namespace {

// Inverse of the standard normal upper tail: z with P(|Z| > z) = p, by bisection on erfc.
double twoSidedZ(double p) {
  double lo = 0, hi = 40;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    if (std::erfc(mid / std::sqrt(2.0)) > p) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

Renderer& testRenderer() {
  static std::unique_ptr<Renderer> renderer;
  if (!renderer) {
    renderer = std::make_unique<Renderer>(testContext());
    destroyBeforeTestContext([] { renderer.reset(); });
  }
  return *renderer;
}

RenderResult renderInTest(const Scene& scene, const RenderOptions& options) { return testRenderer().render(scene, options); }

ZTestResult zTest(const std::vector<float>& a, const std::vector<float>& aVariance, const std::vector<float>& b,
                  const std::vector<float>& bVariance, double alpha) {
  ZTestResult r;
  double worstZ = -1;
  r.tested = a.size();
  // Sidak: per-test level so that the chance of any false rejection over all pixels is alpha.
  double perTest = 1.0 - std::pow(1.0 - alpha, 1.0 / double(std::max<size_t>(r.tested, 1)));
  r.threshold = twoSidedZ(perTest);
  for (size_t i = 0; i < a.size(); ++i) {
    bool aBlind = a[i] == 0.0f && aVariance[i] == 0.0f, bBlind = b[i] == 0.0f && bVariance[i] == 0.0f;
    if (aBlind != bBlind && (aBlind ? bVariance[i] : aVariance[i]) > 0.0f) {
      // Not tested: the blind side's chance of missing every sample depends on its own
      // estimator's hit probability, which neither side's variance measures (a pure path
      // tracer facing one with NEE may well see nothing at a small light's pixel). Callers cap
      // how many such pixels they accept; the image-mean comparison still covers them.
      r.untestable++;
      continue;
    }
    double variance = double(aVariance[i]) + double(bVariance[i]);
    double diff = double(a[i]) - double(b[i]);
    double z = variance > 0 ? std::abs(diff) / std::sqrt(variance) : (diff == 0 ? 0.0 : INFINITY);
    if (z > r.threshold) r.rejected++;
    if (z > worstZ) {
      worstZ = z;
      std::ostringstream text;
      text << "pixel " << i << ": " << a[i] << " vs " << b[i] << " (z = " << z << ", threshold " << r.threshold << ")";
      r.worst = text.str();
    }
  }
  return r;
}

ImageMean imageMean(const std::vector<float>& mean, const std::vector<float>& variance) {
  ImageMean m;
  double sum = 0, var = 0;
  for (size_t i = 0; i < mean.size(); ++i) {
    sum += mean[i];
    var += variance[i];
  }
  double n = double(std::max<size_t>(mean.size(), 1));
  m.mean = sum / n;
  m.standardError = std::sqrt(var) / n;
  return m;
}

}  // namespace vktg::test
