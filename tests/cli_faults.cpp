// Device and resource faults, end to end: a render too large for the device, an allocation that
// fails, a lost device, a submission that never finishes (VKTG_INJECT_FAULT, src/host/
// fault_injection.h, provokes the last three on lavapipe), and SIGINT / SIGTERM mid-render. Each
// must end with one `vktg: error:` line naming the fault, a non-zero status (128 + the signal for
// an interruption) and the working directory unchanged: no output, partial or complete.
#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "support/cli_runner.h"

namespace vktg::test {
namespace {

// A render of the built-in scene in many small batches (16 MiB of wavefront state for 4M paths),
// long enough to be interrupted between two of them.
std::vector<std::string> manyBatches(const TempDir& dir) {
  return {"render", "--resolution", "32x32", "--spp", "4096", "--mem", "16", "--out", (dir / "out.exr").string()};
}

void expectFaultWithoutOutput(const std::vector<std::string>& args, const CliOptions& options, const TempDir& dir,
                              int exitCode, const std::vector<std::string>& keywords) {
  const auto before = directorySnapshot(dir);
  CliResult r = runVktg(args, options);
  ASSERT_FALSE(r.timedOut) << r.describe();
  ASSERT_TRUE(r.exited) << "the process did not exit normally\n" << r.describe();
  EXPECT_EQ(r.exitCode, exitCode) << r.describe();
  std::vector<std::string> errors = linesStartingWith(r.err, "vktg: error: ");
  ASSERT_EQ(errors.size(), 1u) << r.describe();
  for (const std::string& word : keywords)
    EXPECT_NE(errors[0].find(word), std::string::npos) << "the error does not mention '" << word << "': " << errors[0];
  EXPECT_EQ(directorySnapshot(dir), before) << "the run left files behind\n" << r.describe();
}

TEST(CliFaults, RenderLargerThanTheDeviceFailsBeforeItStarts) {
  // 16384^2 pixels x 1000 bins: terabytes of film, far beyond any device, within --mem's range.
  TempDir dir;
  expectFaultWithoutOutput({"render", "--resolution", "16384x16384", "--gate", "bins:0,0.01,1000", "--spp", "1", "--mem",
                            "1048576", "--out", (dir / "out.exr").string()},
                           {.cwd = dir.path(), .timeoutSeconds = 120}, dir, 1,
                           {"needs at least", "MiB of device memory", "film", "16384 x 16384 pixels x 1000 layers"});
}

TEST(CliFaults, RenderLargerThanTheBudgetNamesWhatItNeeds) {
  TempDir dir;
  expectFaultWithoutOutput({"render", "--resolution", "512x512", "--gate", "bins:0,0.1,64", "--spp", "1", "--mem", "16",
                            "--out", (dir / "out.exr").string()},
                           {.cwd = dir.path(), .timeoutSeconds = 120}, dir, 1, {"--mem", "needs at least", "film"});
}

TEST(CliFaults, FailedAllocationIsOneClearError) {
  TempDir dir;
  expectFaultWithoutOutput(manyBatches(dir), {.env = {{"VKTG_INJECT_FAULT", "alloc:3"}}, .cwd = dir.path()}, dir, 1,
                           {"out of device memory allocating", "MiB"});
}

TEST(CliFaults, LostDeviceIsOneClearError) {
  // The first submission clears the counters and the film; the second runs the first batch.
  TempDir dir;
  expectFaultWithoutOutput(manyBatches(dir), {.env = {{"VKTG_INJECT_FAULT", "submit:2:lost"}}, .cwd = dir.path()}, dir,
                           1, {"VK_ERROR_DEVICE_LOST"});
}

TEST(CliFaults, FenceTimeoutIsOneClearError) {
  TempDir dir;
  expectFaultWithoutOutput(manyBatches(dir), {.env = {{"VKTG_INJECT_FAULT", "submit:3:timeout"}}, .cwd = dir.path()},
                           dir, 1, {"fence timeout"});
}

TEST(CliFaults, MalformedFaultInjectionIsRejected) {
  TempDir dir;
  expectFaultWithoutOutput(manyBatches(dir), {.env = {{"VKTG_INJECT_FAULT", "submit:x"}}, .cwd = dir.path()}, dir, 1,
                           {"VKTG_INJECT_FAULT", "submit:x"});
}

TEST(CliFaults, AnObjectNeverDestroyedFailsTheRunAtExit) {
  // The validation layer names what was never destroyed only when the device goes, after the
  // command's own check: the context reports it and main() turns the exit status into 3.
  TempDir dir;
  CliResult r = runVktg({"render", "--spp", "1", "--resolution", "8x8", "--quiet", "--out", (dir / "l.exr").string()},
                        {.env = {{"VKTG_INJECT_FAULT", "leak:1"}}, .cwd = dir.path()});
  EXPECT_EQ(r.exitCode, 3) << r.describe();
  EXPECT_NE(r.err.find("vktg: validation at exit:"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("VkDeviceMemory"), std::string::npos) << r.describe();
  // Without the leak the same run is clean.
  CliResult clean = runVktg({"render", "--spp", "1", "--resolution", "8x8", "--quiet", "--out", (dir / "c.exr").string()},
                            {.cwd = dir.path()});
  EXPECT_EQ(clean.exitCode, 0) << clean.describe();
  EXPECT_EQ(clean.err.find("validation"), std::string::npos) << clean.describe();
}

class CliInterrupt : public ::testing::TestWithParam<int> {};

TEST_P(CliInterrupt, StopsBetweenBatchesWithoutOutput) {
  // Signalled once the first batch reported progress; the render stops after the batch in flight.
  TempDir dir;
  const int signal = GetParam();
  expectFaultWithoutOutput(manyBatches(dir), {.cwd = dir.path(), .signalWhen = "render: 0%", .signal = signal}, dir,
                           128 + signal, {"interrupted by", signal == SIGINT ? "SIGINT" : "SIGTERM"});
}

INSTANTIATE_TEST_SUITE_P(Signals, CliInterrupt, ::testing::Values(SIGINT, SIGTERM),
                         [](const auto& info) { return std::string(info.param == SIGINT ? "Sigint" : "Sigterm"); });

}  // namespace
}  // namespace vktg::test
