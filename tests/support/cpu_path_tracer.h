// An independent brute-force reference for steady (and gated) rendering: pure BSDF sampling,
// diffuse materials only, emission collected where a path hits the front face of an emitter; no
// next-event estimation, no MIS, no Russian roulette. It shares only the scene flattening
// (vktg::prepareScene) and the CPU BVH traversal (vktg::traceClosest) with the renderer, and
// accumulates in double precision.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "vktg/scene.h"

namespace vktg::test {

struct CpuRenderResult {
  uint32_t width = 0, height = 0;
  std::vector<double> mean;      // per pixel, row 0 at the top
  std::vector<double> variance;  // variance of each pixel's mean
};

// Renders `spp` paths per pixel with paths of at most `maxDepth` segments (vertices after the
// camera). Camera model as shaders/generate_camera_rays.comp: perspective pixels are box-filtered
// over the image plane (ray = normalize(F + (2px - 1) R + (1 - 2py) U)), a point sensor measures
// cosine-weighted irradiance about its normal. `gate` weights each emitter hit by W(path length)
// (null: steady). Throws std::runtime_error for non-diffuse materials or point lights.
CpuRenderResult cpuPathTrace(const Scene& scene, uint32_t spp, uint32_t maxDepth, uint64_t seed,
                             const std::function<double(double)>& gate = nullptr);

}  // namespace vktg::test
