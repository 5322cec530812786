// Sets an environment variable for its lifetime (the variables through which tests force a
// device's choices: VKTG_SCENE_ACCESS, VKTG_BVH_WIDTH, VKTG_DEVICE_MEMORY, VKTG_MAX_CHUNK_BYTES,
// VKTG_SHADOW_SLOTS).
#pragma once
#include <cstdlib>

namespace vktg::test {

struct ScopedEnv {
  ScopedEnv(const char* name, const char* value) : name(name) { setenv(name, value, 1); }
  ~ScopedEnv() { unsetenv(name); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;
  const char* name;
};

}  // namespace vktg::test
