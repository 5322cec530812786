#include "scene/selection_cdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vktg {

std::vector<uint64_t> selectionIntervalEnds(const std::vector<double>& weights, uint64_t scale) {
  if (weights.size() > scale) throw std::length_error("selectionIntervalEnds: more items than selection numbers");
  double total = 0;
  for (double w : weights) total += w;
  std::vector<uint64_t> ends(weights.size());
  double cdf = 0;
  uint64_t start = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    cdf += weights[i] / total;
    // One integer at least for this item and for each after it.
    const uint64_t later = weights.size() - 1 - i;
    ends[i] = later == 0 ? scale
                         : std::clamp<uint64_t>(uint64_t(std::llround(cdf * double(scale))), start + 1, scale - later);
    start = ends[i];
  }
  return ends;
}

}  // namespace vktg
