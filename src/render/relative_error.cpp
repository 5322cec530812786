#include "render/relative_error.h"

#include <cstddef>

namespace vktg {

namespace {

// relMSE's regulariser: 1e-2 mean(r)^2, so that dark pixels do not dominate (0 for one pixel).
double relMseEpsilon(const std::vector<float>& ref) {
  double meanRef = 0;
  for (float r : ref) meanRef += r;
  meanRef /= double(ref.size());
  return ref.size() == 1 ? 0.0 : 1e-2 * meanRef * meanRef;
}

}  // namespace

double relMse(const std::vector<float>& x, const std::vector<float>& ref) {
  const double eps = relMseEpsilon(ref);
  double sum = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    double d = double(x[i]) - double(ref[i]);
    sum += d * d / (double(ref[i]) * ref[i] + eps);
  }
  return sum / double(x.size());
}

double expectedRelMse(const std::vector<float>& variance, const std::vector<float>& ref) {
  const double eps = relMseEpsilon(ref);
  double sum = 0;
  for (size_t i = 0; i < variance.size(); ++i) sum += double(variance[i]) / (double(ref[i]) * ref[i] + eps);
  return sum / double(variance.size());
}

}  // namespace vktg
