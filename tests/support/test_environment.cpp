#include "support/test_environment.h"

#include <cstdlib>

namespace vktg::test {

void applyTestEnvironment() {
  // setenv(..., 0) keeps a value the user set: "unless told otherwise".
  setenv("VK_DRIVER_FILES", VKTG_TEST_ICD, 0);
  setenv("VK_ICD_FILENAMES", std::getenv("VK_DRIVER_FILES"), 0);
  setenv("VKTG_VALIDATION", "1", 0);
}

}  // namespace vktg::test
