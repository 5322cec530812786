// Scenes the benchmarks generate: the default room with a tessellated floor of any size, so that
// costs can be measured as the triangle count grows.
#pragma once
#include <cstdint>

#include "vktg/scene.h"

namespace vktg {

// The default room, its two boxes replaced by an n x n heightfield of smooth bumps (up to ~0.2 m)
// covering the floor (2 (n-1)^2 triangles), at `resolution` x `resolution` pixels, under a gaussian
// gate at 7 m, sigma / mu = 1e-2: two- and three-bounce paths.
Scene tessellatedRoom(uint32_t n, uint32_t resolution);

}  // namespace vktg
