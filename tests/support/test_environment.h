// The environment every GPU and CLI test runs in, applied by the test binaries themselves so a
// test behaves the same under ctest and when run by hand. VKTG_TEST_DEVICE picks the device:
//   unset or "lavapipe"  lavapipe only (VKTG_TEST_ICD), unless VK_DRIVER_FILES names another driver
//   "gpu"                the best usable GPU among all installed drivers
//   an index or a name   that device, as `vktg --device` takes it (`vktg info` lists them)
// Validation is on unless VKTG_VALIDATION=0, and the device buffers' guards (host/memory_guard.h)
// unless VKTG_GUARD_MEMORY=0.
#pragma once

namespace vktg::test {
void applyTestEnvironment();
}  // namespace vktg::test
