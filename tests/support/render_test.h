// Rendering inside tests: the shared test context (lavapipe, validation on) and the statistics
// that compare renders with references using their measured standard errors.
#pragma once
#include <string>
#include <vector>

#include "render/renderer.h"
#include "vktg/scene.h"

namespace vktg::test {

// The test binary's one Renderer, on the test context (created after the context, so destroyed
// before it).
Renderer& testRenderer();
// Renders with testRenderer().
RenderResult renderInTest(const Scene& scene, const RenderOptions& options = {});

// Per-pixel two-sided z-test of `a` against `b` (each with the variance of its mean; `bVariance`
// may be all zeros for an exact reference). Returns the number of pixels whose |z| exceeds the
// Sidak-corrected threshold for `alpha` over all pixels tested, and writes a description of the
// worst pixel to `worst`. Pixels where both variances are zero must agree exactly.
// A pixel where one side saw no light at all (mean 0 with variance 0) while the other did cannot
// be z-tested as a difference: an all-zero sample mean has no variance estimate. Such pixels are
// counted (`untestable`) and skipped; callers cap their number (the image-mean comparison covers
// their values).
struct ZTestResult {
  size_t tested = 0;
  size_t untestable = 0;
  size_t rejected = 0;
  double threshold = 0;
  std::string worst;
};
ZTestResult zTest(const std::vector<float>& a, const std::vector<float>& aVariance, const std::vector<float>& b,
                  const std::vector<float>& bVariance, double alpha = 1e-3);

// Mean of a whole image and the standard error of that mean (pixels are independent).
struct ImageMean {
  double mean = 0;
  double standardError = 0;
};
ImageMean imageMean(const std::vector<float>& mean, const std::vector<float>& variance);

}  // namespace vktg::test
