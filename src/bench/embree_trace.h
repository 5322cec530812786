// The same rays through Intel Embree on the host's cores, for `vktg bench trace` to put the
// renderer's traversal beside a production CPU ray tracer. Embree is an optional benchmark
// dependency (libembree-dev, found at configure time), never a renderer one.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/prepared_scene.h"

namespace vktg {

struct TraceRay {
  glm::vec3 origin;
  float tMin;
  glm::vec3 direction;
  float tMax;
};

struct EmbreeTiming {
  double raysPerSecond = 0;   // median over runs, all hardware threads
  std::vector<bool> hits;     // per ray: a closest hit found / the ray is occluded
};

// Empty when vktg was built without Embree; else its version.
std::string embreeVersion();

// Traces `rays` (closest hit, or any hit) through the prepared scene's triangles, repeating the
// whole set until `budgetSeconds`, `runs` times; nullopt without Embree.
std::optional<EmbreeTiming> embreeTrace(const PreparedScene& scene, const std::vector<TraceRay>& rays, bool anyHit,
                                        double budgetSeconds, uint32_t runs);

}  // namespace vktg
