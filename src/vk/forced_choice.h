// The environment variables through which tests and benchmarks force one of a device's two choices
// (VKTG_SCENE_ACCESS, VKTG_BVH_WIDTH, VKTG_DEVICE_MEMORY, VKTG_SHADOW_SLOTS, VKTG_EDGE_DISPATCH,
// VKTG_PIPELINE_CREATION, VKTG_SCATTER, VKTG_BOUNDARY_SAMPLES): the default follows the device, or
// is the same on every device.
#pragma once
#include <cstdlib>
#include <optional>
#include <string>

#include "vktg/error.h"

namespace vktg {

// True for `first`, false for `second`, nothing when unset; anything else is an error naming it.
inline std::optional<bool> forcedChoice(const char* variable, const char* first, const char* second) {
  const char* value = std::getenv(variable);
  if (!value || !*value) return std::nullopt;
  if (std::string(value) == first) return true;
  if (std::string(value) == second) return false;
  throw Error(std::string(variable) + ": '" + value + "' is neither '" + first + "' nor '" + second + "'");
}

}  // namespace vktg
