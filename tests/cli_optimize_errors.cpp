// `vktg optimize` with bad input: every case exits non-zero with one message naming the file, the
// field and the problem, before the run directory is created or changed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "support/cli_runner.h"
#include "support/table_case_name.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::runVktg;
using test::TempDir;

const fs::path kData = fs::path(VKTG_TEST_DATA) / "optimize";

// An experiment over terrain.json (8 x 8 pixels, box gate) with one target image and one parameter.
std::string experiment(const std::string& image, const std::string& parameter = R"({"name": "grey", "initial": 0.3})",
                       const std::string& extra = "") {
  return R"({"version": 1, "scene": ")" + (kData / "terrain.json").string() + R"(", "parameters": [)" + parameter +
         R"(], "targets": [{"name": "front", )" + image + "}]" + extra + "}";
}

ImageSet image(uint32_t width, uint32_t height, uint32_t layers, float value) {
  ImageSet set{width, height, {}};
  for (uint32_t l = 0; l < layers; ++l)
    set.layers.push_back({layers == 1 ? "" : "bin" + std::to_string(l), std::vector<float>(size_t(width) * height, value)});
  return set;
}

struct BadExperiment {
  const char* name;
  std::string text;
  std::vector<std::string> expected;  // besides the experiment file's path
};

class OptimizeBadInput : public testing::TestWithParam<BadExperiment> {};

TEST_P(OptimizeBadInput, FailsBeforeWritingAnything) {
  const BadExperiment& c = GetParam();
  TempDir dir;
  writeExr(dir / "small.exr", image(4, 4, 1, 0.1f));
  writeExr(dir / "right.exr", image(8, 8, 1, 0.1f));
  writeExr(dir / "nan.exr", [] {
    ImageSet i = image(8, 8, 1, 0.1f);
    i.layers[0].pixels[17] = std::numeric_limits<float>::quiet_NaN();
    return i;
  }());
  const fs::path file = dir / "experiment.json";
  test::writeFileBytes(file, c.text);
  const test::CliResult r = runVktg({"optimize", file.string(), "--out", (dir / "run").string()});
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_NE(r.exitCode, 0) << r.describe();
  EXPECT_NE(r.err.find(file.string()), std::string::npos) << r.err;
  for (const std::string& part : c.expected) EXPECT_NE(r.err.find(part), std::string::npos) << "'" << part << "' in " << r.err;
  EXPECT_FALSE(fs::exists(dir / "run")) << "the run directory was created";
}

const BadExperiment kBad[] = {
    {"TargetOfTheWrongSize", experiment(R"("image": "small.exr")"), {"targets[0].image", "small.exr is 4x4", "render 8x8"}},
    {"TargetWithTooFewLayers", experiment(R"("image": "right.exr", "gate": {"spec": "bins:2,0.5,8"})"),
     {"targets[0].image", "8 layers"}},
    {"MissingTarget", experiment(R"("image": "absent.exr")"), {"targets[0].image", "absent.exr"}},
    {"TargetHoldingNaN", experiment(R"("image": "nan.exr")"), {"targets[0].image", "NaN"}},
    {"UnknownParameter", experiment(R"("image": "right.exr")", R"({"name": "nope", "initial": 0})"),
     {"parameters[0].name", "nope"}},
    {"InitialValueOutOfRange", experiment(R"("image": "right.exr")", R"({"name": "grey", "initial": 1.5})"),
     {"parameters[0].initial", "1.5"}},
    {"ZeroLearningRate", experiment(R"("image": "right.exr")", R"({"name": "grey", "initial": 0.3})",
                                    R"(, "optimizer": {"type": "adam", "learning_rate": 0})"),
     {"optimizer.learning_rate"}},
    {"NegativeLearningRate", experiment(R"("image": "right.exr")", R"({"name": "grey", "initial": 0.3})",
                                        R"(, "optimizer": {"type": "sgd", "learning_rate": -0.1})"),
     {"optimizer.learning_rate"}},
    {"SynthesisWithoutTruth", experiment(R"("image": {"synthesize": {}})"), {"targets[0].image", "truth"}},
};

INSTANTIATE_TEST_SUITE_P(Table, OptimizeBadInput, testing::ValuesIn(kBad), test::tableCaseName<BadExperiment>);

TEST(OptimizeTooLarge, FailsBeforeTheRunDirectoryWithWhatItNeeds) {
  // 8 x 8 pixels x 65536 bins: a 64 MiB film, against a 16 MiB budget.
  TempDir dir;
  const fs::path file = dir / "experiment.json";
  test::writeFileBytes(file, experiment(R"("gate": {"spec": "bins:0,0.001,65536"}, "image": {"synthesize": {}})",
                                        R"({"name": "grey", "initial": 0.3, "truth": 0.2})"));
  const test::CliResult r = runVktg({"optimize", file.string(), "--out", (dir / "run").string(), "--mem", "16"});
  ASSERT_TRUE(r.exited) << r.describe();
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  for (const std::string part : {file.string(), std::string("targets[0]"), std::string("--mem"),
                                 std::string("needs at least"), std::string("8 x 8 pixels x 65536 layers")})
    EXPECT_NE(r.err.find(part), std::string::npos) << "'" << part << "' in " << r.err;
  EXPECT_FALSE(fs::exists(dir / "run")) << "the run directory was created";
}

// A valid one-iteration experiment in `dir` (its target image beside it): the run directory is
// what these tests get wrong.
fs::path oneIterationExperiment(const fs::path& dir) {
  writeExr(dir / "right.exr", image(8, 8, 1, 0.1f));
  const fs::path file = dir / "experiment.json";
  test::writeFileBytes(file, experiment(R"("image": "right.exr")", R"({"name": "grey", "initial": 0.3})",
                                        R"(, "stop": {"iterations": 1})"));
  return file;
}

TEST(OptimizeBadRunDirectory, UnwritableOrForeignDirectoriesAreRefused) {
  TempDir dir;
  const fs::path file = oneIterationExperiment(dir.path());
  // Below a regular file no directory can be made (a means that works as root too).
  test::writeFileBytes(dir / "plain", "not a directory");
  test::CliResult r = runVktg({"optimize", file.string(), "--out", (dir / "plain" / "run").string()});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("cannot create the run directory"), std::string::npos) << r.err;
  // --force replaces runs only, never a directory holding other files.
  fs::create_directories(dir / "mine");
  test::writeFileBytes(dir / "mine" / "thesis.tex", "keep me");
  r = runVktg({"optimize", file.string(), "--out", (dir / "mine").string(), "--force"});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("thesis.tex"), std::string::npos) << r.err;
  EXPECT_EQ(test::readFileBytes(dir / "mine" / "thesis.tex"), "keep me");
  // --resume of a directory that holds no run.
  r = runVktg({"optimize", "--resume", (dir / "mine").string()});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("run.json"), std::string::npos) << r.err;
}

TEST(OptimizeBadRunDirectory, AResumedRunRefusesANegativeTermPilotCount) {
  TempDir dir;
  const fs::path file = oneIterationExperiment(dir.path());
  test::CliResult r = runVktg({"optimize", file.string(), "--out", (dir / "run").string()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  // run.json as a pilot would have left it, but with a count no pilot gives.
  std::string info = test::readFileBytes(dir / "run" / "run.json");
  const size_t end = info.rfind('}');
  ASSERT_NE(end, std::string::npos) << info;
  info.insert(end, R"(, "term_pilot": {"spp_edge": -0.5, "spp_boundary": 1, "spp_boundary_camera": 1})");
  test::writeFileBytes(dir / "run" / "run.json", info);
  const std::string log = test::readFileBytes(dir / "run" / "log.csv");
  r = runVktg({"optimize", "--resume", (dir / "run").string(), "--iterations", "2"});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("run.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("term_pilot.spp_edge"), std::string::npos) << r.err;
  EXPECT_EQ(test::readFileBytes(dir / "run" / "log.csv"), log);
}

}  // namespace
}  // namespace vktg
