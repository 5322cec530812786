// `mpirun -np N vktg render|grad|optimize` (docs/mpi.md) on lavapipe, the processes sharing it: the
// outputs are the bytes one process without mpirun writes, for N = 2 and 3 (five scan points split
// 3 + 2 and 2 + 2 + 1); an optimisation stopped under one N and resumed under another ends where the
// uninterrupted one-process run does, and one stopped by Ctrl-C on mpirun leaves a checkpoint that
// resumes; a process that fails or is killed ends every process with an error, within seconds,
// instead of leaving its peers waiting.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "opt/run_files.h"
#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kScene = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan" / "scene.json";

// Five confocal points in a row across the relay wall (the sensor and the laser at each).
fs::path writeScan(const TempDir& dir) {
  writeJsonFile(dir / "scan.json", {{"version", 1},
                                    {"grid",
                                     {{"corner", {-0.4, 1.0, 0.0}}, {"across", {0.8, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.1}},
                                      {"resolution", {5, 1}}, {"lights", {"laser"}}}}});
  return dir / "scan.json";
}

// Every run here goes without the validation layer, which would triple lavapipe's time: the runs
// compare bytes with each other, and the passes they run are those the other tests validate.
const std::map<std::string, std::string> kWithoutValidation = {{"VKTG_VALIDATION", "0"}};

// mpirun -np N [WRAPPER...] vktg ARGS, in `dir` (as root, several processes on two cores).
CliResult runMpi(int processes, const std::vector<std::string>& args, const TempDir& dir,
                 const std::vector<std::string>& wrapper = {}, double timeoutSeconds = 180,
                 const std::string& interruptWhen = "") {
  std::vector<std::string> argv = {VKTG_MPIEXEC, "--oversubscribe", "-np", std::to_string(processes)};
  argv.insert(argv.end(), wrapper.begin(), wrapper.end());
  argv.push_back(VKTG_BINARY);
  argv.insert(argv.end(), args.begin(), args.end());
  CliOptions options;
  options.env = kWithoutValidation;
  options.env["OMPI_ALLOW_RUN_AS_ROOT"] = "1";
  options.env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1";
  options.cwd = dir.path();
  options.timeoutSeconds = timeoutSeconds;
  options.signalWhen = interruptWhen;  // then SIGINT to mpirun, as Ctrl-C
  return runProgram(argv, options);
}

void expectSuccess(const CliResult& r) {
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_EQ(r.exitCode, 0) << r.describe();
  EXPECT_TRUE(linesStartingWith(r.err, "vktg: error:").empty()) << r.describe();
}

// The reference: one process, no mpirun.
void runAlone(const std::vector<std::string>& args, const TempDir& dir) {
  expectSuccess(runVktg(args, {.env = kWithoutValidation, .cwd = dir.path()}));
}

double absoluteSum(const fs::path& exr) {
  double sum = 0;
  for (const ImageLayer& layer : readExr(exr).layers)
    for (float v : layer.pixels) sum += std::abs(double(v));
  return sum;
}

TEST(MpiRender, ScanIsTheOneProcessBytesForTwoAndThreeProcesses) {
  TempDir dir;
  const fs::path scan = writeScan(dir);
  auto render = [&](const std::string& out) {
    return std::vector<std::string>{"render", kScene.string(), "--scan", scan.string(), "--spp", "4", "--seed", "7",
                                    "--nee", "standard", "--npy", "--out", (dir / out).string()};
  };
  runAlone(render("one.exr"), dir);
  ASSERT_GT(absoluteSum(dir / "one.exr"), 0) << "the hidden surface returns light";
  for (int n : {2, 3}) {
    const std::string out = "n" + std::to_string(n);
    const CliResult r = runMpi(n, render(out + ".exr"), dir);
    expectSuccess(r);
    EXPECT_NE(r.err.find("5 scan views (5 x 1) over " + std::to_string(n) + " processes"), std::string::npos) << r.describe();
    EXPECT_EQ(readFileBytes(dir / (out + ".exr")), readFileBytes(dir / "one.exr")) << n << " processes";
    EXPECT_EQ(readFileBytes(dir / (out + ".npy")), readFileBytes(dir / "one.npy")) << n << " processes";
  }
}

TEST(MpiGrad, ScanIsTheOneProcessBytesForTwoAndThreeProcesses) {
  TempDir dir;
  const fs::path scan = writeScan(dir);
  auto grad = [&](const std::string& out) {
    return std::vector<std::string>{"grad", kScene.string(), "--scan", scan.string(), "--spp", "4", "--seed", "7",
                                    "--nee", "standard", "--param", "h28,h35", "--terms", "interior,pathlength",
                                    "--gate", "bins:1.6,0.2,5", "--split-terms", "--out", (dir / out).string()};
  };
  runAlone(grad("one.exr"), dir);
  ASSERT_GT(absoluteSum(dir / "one.exr"), 0) << "the heights move the transients";
  for (int n : {2, 3}) {
    const std::string out = "n" + std::to_string(n);
    expectSuccess(runMpi(n, grad(out + ".exr"), dir));
    for (const std::string& file : {".exr", ".interior.exr", ".pathlength.exr"})
      EXPECT_EQ(readFileBytes(dir / (out + file)), readFileBytes(dir / ("one" + file))) << n << " processes, " << file;
  }
}

// The log without its last column (each run's own seconds).
std::vector<std::string> logWithoutSeconds(const fs::path& csv) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(line.substr(0, line.rfind(',')));
  return rows;
}

void expectSameRun(const fs::path& run, const fs::path& reference) {
  for (const char* file : {"parameters.json", "scene.json"})
    EXPECT_EQ(readFileBytes(run / file), readFileBytes(reference / file)) << run << ": " << file;
  EXPECT_EQ(logWithoutSeconds(run / "log.csv"), logWithoutSeconds(reference / "log.csv")) << run;
  for (const auto& entry : fs::directory_iterator(reference / "targets"))
    EXPECT_EQ(readFileBytes(run / "targets" / entry.path().filename()), readFileBytes(entry.path())) << entry.path();
  const Checkpoint a = readCheckpoint(run / "checkpoint.bin"), b = readCheckpoint(reference / "checkpoint.bin");
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.theta, b.theta) << run;
  EXPECT_EQ(a.bvhTheta, b.bvhTheta);
  EXPECT_EQ(a.optimizer.steps, b.optimizer.steps);
  EXPECT_EQ(a.optimizer.first, b.optimizer.first);
  EXPECT_EQ(a.optimizer.second, b.optimizer.second);
  EXPECT_EQ(a.adjointScale, b.adjointScale);
  EXPECT_EQ(a.initialLoss, b.initialLoss);
}

fs::path writeExperiment(const TempDir& dir) {
  const fs::path scan = writeScan(dir);
  writeJsonFile(dir / "experiment.json",
                {{"version", 1},
                 {"scene", kScene.string()},
                 {"parameters", {{{"name", "h*"}, {"initial", 0.01}, {"truth", 0}, {"range", {-0.5, 0.5}}}}},
                 {"targets",
                  {{{"name", "scan"},
                    {"scan", scan.string()},
                    {"image", {{"synthesize", {{"spp", 16}}}}},
                    {"gate", {{"type", "bins"}, {"start", 1.6}, {"width", 0.2}, {"count", 5}}}}}},
                 {"loss", {{"type", "l2"}}},
                 {"optimizer", {{"type", "adam"}, {"learning_rate", 0.03}}},
                 {"regularizers", {{{"type", "laplacian"}, {"shape", "hidden"}, {"weight", 0.05}}}},
                 {"render", {{"spp", 4}, {"spp_interior", 4}, {"spp_boundary", 4}, {"terms", {"interior", "pathlength"}}}},
                 {"stop", {{"iterations", 2}}},
                 {"checkpoint_every", 1},
                 {"images_every", 1},
                 {"seed", 1}});
  return dir / "experiment.json";
}

TEST(MpiOptimize, ThreeProcessesThenTwoOnResumingEndWhereOneProcessDoes) {
  TempDir dir;
  const fs::path experiment = writeExperiment(dir);
  runAlone({"optimize", experiment.string(), "--out", (dir / "one").string()}, dir);
  ASSERT_EQ(logWithoutSeconds(dir / "one" / "log.csv").size(), 3u) << "a header and two iterations";
  ASSERT_NE(readCheckpoint(dir / "one" / "checkpoint.bin").theta, std::vector<double>(64, 0.01)) << "θ moved";

  // Three processes for the first iteration (synthesis and the loss split 2 + 2 + 1, its θ step
  // from their summed gradient), two for the second (3 + 2), resumed from the first's checkpoint.
  expectSuccess(runMpi(3, {"optimize", experiment.string(), "--out", (dir / "resumed").string(), "--iterations", "1"}, dir));
  EXPECT_EQ(readCheckpoint(dir / "resumed" / "checkpoint.bin").iteration, 1u);
  expectSuccess(runMpi(2, {"optimize", "--resume", (dir / "resumed").string()}, dir));
  expectSameRun(dir / "resumed", dir / "one");
}

TEST(MpiOptimize, CtrlCOnMpirunLeavesACheckpointThatResumes) {
  TempDir dir;
  const fs::path experiment = writeExperiment(dir), run = dir / "run";
  const CliResult r = runMpi(2, {"optimize", experiment.string(), "--out", run.string(), "--iterations", "100000"}, dir, {},
                             90, "iteration 1/");
  ASSERT_FALSE(r.timedOut) << r.describe();
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_NE(r.exitCode, 0) << r.describe();
  EXPECT_NE(r.err.find("checkpoint written"), std::string::npos) << r.describe();
  const Checkpoint stopped = readCheckpoint(run / "checkpoint.bin");
  ASSERT_GE(stopped.iteration, 1u);
  // One more iteration, by one process.
  runAlone({"optimize", "--resume", run.string(), "--iterations", std::to_string(stopped.iteration + 1)}, dir);
  EXPECT_EQ(readCheckpoint(run / "checkpoint.bin").iteration, stopped.iteration + 1);
  EXPECT_EQ(logWithoutSeconds(run / "log.csv").size(), stopped.iteration + 2) << "a header and a row per iteration";
}

// A shell script run by every process in front of vktg: `rank1` is what rank 1 runs first.
std::vector<std::string> wrapper(const TempDir& dir, const std::string& rank1) {
  const fs::path script = dir / "wrapper.sh";
  std::ofstream(script) << "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then\n" << rank1 << "\nfi\nexec \"$@\"\n";
  return {"/bin/sh", script.string()};
}

TEST(MpiFailure, ADeviceLostInOneProcessEndsEveryProcessWithItsError) {
  TempDir dir;
  const fs::path scan = writeScan(dir);
  const CliResult r = runMpi(2,
                             {"render", kScene.string(), "--scan", scan.string(), "--spp", "4", "--nee", "standard", "--out",
                              (dir / "out.exr").string()},
                             dir, wrapper(dir, "export VKTG_INJECT_FAULT=submit:1:lost"), 90);
  ASSERT_FALSE(r.timedOut) << r.describe();
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_NE(r.exitCode, 0) << r.describe();
  const std::vector<std::string> errors = linesStartingWith(r.err, "vktg: error: rank 1 of 2: ");
  ASSERT_EQ(errors.size(), 1u) << r.describe();
  EXPECT_NE(errors[0].find("device was lost"), std::string::npos) << errors[0];
  EXPECT_FALSE(fs::exists(dir / "out.exr")) << "rank 0 wrote an image without rank 1's views";
}

TEST(MpiFailure, AKilledProcessEndsTheRunWithinSeconds) {
  TempDir dir;
  const fs::path experiment = writeExperiment(dir);
  // Rank 1 is killed 5 s after it starts: synthesising targets or somewhere in the iterations.
  const double killAfter = 5;
  const CliResult r = runMpi(2, {"optimize", experiment.string(), "--out", (dir / "run").string(), "--iterations", "100000"},
                             dir, wrapper(dir, "(sleep 5; kill -9 $$) &"), 90);
  ASSERT_FALSE(r.timedOut) << "rank 0 waited for the killed process\n" << r.describe();
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_NE(r.exitCode, 0) << r.describe();
  EXPECT_LT(r.seconds, killAfter + 20) << r.describe();
  EXPECT_NE(r.err.find("rank 1"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("signal 9"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace vktg::test
