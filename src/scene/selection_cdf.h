// Discrete selection in fixed point, for the CDFs the shaders invert (lights, silhouette edges).
#pragma once
#include <cstdint>
#include <vector>

namespace vktg {

// Item i owns the integers [end_{i-1}, end_i) of [0, scale) (end_{-1} = 0, the last end = scale),
// at least one each, otherwise as near its share of `weights` (non-negative, some positive) as
// rounding allows. A sampler that compares a uniform integer of [0, scale) against the ends picks
// item i with probability exactly (end_i - end_{i-1}) / scale: the pmf the sample must divide by.
// A float CDF inverted with float numbers agrees with its pmfs only to a step of those numbers,
// which is most of an item's share once there are millions. Throws when there are more items
// than integers.
std::vector<uint64_t> selectionIntervalEnds(const std::vector<double>& weights, uint64_t scale);

}  // namespace vktg
