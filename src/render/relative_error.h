// The relative mean squared error of an image against a reference, measured and expected from the
// image's per-pixel variances: what the benchmarks report and the NEE pilot minimises.
#pragma once
#include <vector>

namespace vktg {

// relMSE = mean over pixels of (x - r)^2 / (r^2 + eps), eps = 1e-2 mean(r)^2 (0 for one pixel):
// the usual definition, made scale-free so dark pixels do not dominate.
double relMse(const std::vector<float>& x, const std::vector<float>& reference);
// The expected relMSE of an unbiased image whose pixels' means have these variances (same eps).
double expectedRelMse(const std::vector<float>& variance, const std::vector<float>& reference);

}  // namespace vktg
