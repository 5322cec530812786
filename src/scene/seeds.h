// Seeds derived from one seed for the independent renders of a run (optimisation iterations and
// targets, scan views): splitmix64's finaliser, so that nearby inputs give unrelated seeds.
#pragma once
#include <cstdint>

namespace vktg {

inline uint32_t derivedSeed(uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 31;
  return uint32_t(x);
}

}  // namespace vktg
