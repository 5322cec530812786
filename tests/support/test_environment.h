// The environment every GPU and CLI test runs in, applied by the test binaries themselves so a
// test behaves the same under ctest and when run by hand: lavapipe (VKTG_TEST_ICD) unless
// VK_DRIVER_FILES names another driver, and validation on unless VKTG_VALIDATION=0.
#pragma once

namespace vktg::test {
void applyTestEnvironment();
}  // namespace vktg::test
