#include "support/test_environment.h"

#include <cstdlib>
#include <string>

namespace vktg::test {

void applyTestEnvironment() {
  const char* device = std::getenv("VKTG_TEST_DEVICE");
  if (!device || std::string(device).empty() || std::string(device) == "lavapipe") {
    // setenv(..., 0) keeps a value the user set: "unless told otherwise".
    setenv("VK_DRIVER_FILES", VKTG_TEST_ICD, 0);
    setenv("VK_ICD_FILENAMES", std::getenv("VK_DRIVER_FILES"), 0);
  } else {
    // Every installed driver stays visible; the device is chosen by name. VKTG_DEVICE reaches the
    // vktg processes the CLI tests start as well as the in-process context.
    setenv("VKTG_DEVICE", device, 1);
  }
  setenv("VKTG_VALIDATION", "1", 0);
  setenv("VKTG_GUARD_MEMORY", "1", 0);  // a pass writing past a buffer's end fails its test (host/memory_guard.h)
}

}  // namespace vktg::test
