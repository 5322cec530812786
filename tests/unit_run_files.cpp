// Run files: checkpoints round-trip bit for bit, and every truncated, garbled or inconsistent file
// is rejected with an error naming it; the CSV log writes exact rows and, on resume, keeps the rows
// the checkpoint covers.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>

#include <gtest/gtest.h>

#include "opt/experiment.h"
#include "opt/run_directory.h"
#include "opt/run_files.h"
#include "support/file_test.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::expectError;
using test::readAll;
using test::writePlain;

const fs::path kData = fs::path(VKTG_TEST_DATA) / "optimize";

class RunFiles : public test::TempDirTest {};

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

Checkpoint sample() {
  Checkpoint c;
  c.iteration = 37;
  c.names = {"h0", "h1", "grey", "t0"};
  c.theta = {1.0 / 3.0, -0.0, 4.9e-324, std::numeric_limits<double>::max()};
  c.optimizer.steps = 37;
  c.optimizer.first = {0.1, -1e-300, 2.5, std::nextafter(1.0, 2.0)};
  c.optimizer.second = {1e-20, 0.0, 3.0, std::numeric_limits<double>::quiet_NaN()};
  c.bvhTheta = {0.3, 0.2, 0.1, 0.0};
  c.seconds = 12.345678901234567;
  c.adjointScale = 0x1p40 / 3.0;
  c.initialLoss = {0.25, 1e-9};
  return c;
}

void expectSame(const Checkpoint& a, const Checkpoint& b) {
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.names, b.names);
  EXPECT_TRUE(sameBits(a.theta, b.theta));
  EXPECT_EQ(a.optimizer.steps, b.optimizer.steps);
  EXPECT_TRUE(sameBits(a.optimizer.first, b.optimizer.first));
  EXPECT_TRUE(sameBits(a.optimizer.second, b.optimizer.second));
  EXPECT_TRUE(sameBits(a.bvhTheta, b.bvhTheta));
  EXPECT_TRUE(sameBits({a.seconds}, {b.seconds}));
  EXPECT_TRUE(sameBits({a.adjointScale}, {b.adjointScale}));
  EXPECT_TRUE(sameBits(a.initialLoss, b.initialLoss));
}

TEST_F(RunFiles, CheckpointRoundTripsBitForBit) {
  const Checkpoint original = sample();
  writeCheckpoint(m_dir / "checkpoint.bin", original);
  expectSame(readCheckpoint(m_dir / "checkpoint.bin"), original);
  // SGD (no second moments), no BVH built yet, no targets: empty arrays round-trip too.
  Checkpoint sgd = original;
  sgd.optimizer.second.clear();
  sgd.bvhTheta.clear();
  sgd.initialLoss.clear();
  writeCheckpoint(m_dir / "checkpoint.bin", sgd);
  expectSame(readCheckpoint(m_dir / "checkpoint.bin"), sgd);
  // The write replaced the file atomically: no temporary file is left beside it.
  EXPECT_EQ(std::distance(fs::directory_iterator(m_dir), fs::directory_iterator()), 1);
}

TEST_F(RunFiles, EveryTruncationIsRejected) {
  writeCheckpoint(m_dir / "full.bin", sample());
  const std::string bytes = readAll(m_dir / "full.bin");
  const fs::path cut = m_dir / "cut.bin";
  for (size_t length = 0; length < bytes.size(); ++length) {
    writePlain(cut, bytes.substr(0, length));
    expectError([&] { readCheckpoint(cut); }, {cut.string()});
  }
}

TEST_F(RunFiles, EveryGarbledByteIsRejected) {
  writeCheckpoint(m_dir / "full.bin", sample());
  const std::string bytes = readAll(m_dir / "full.bin");
  const fs::path garbled = m_dir / "garbled.bin";
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::string copy = bytes;
    copy[i] = char(copy[i] ^ 0x10);
    writePlain(garbled, copy);
    expectError([&] { readCheckpoint(garbled); }, {garbled.string()});
  }
  std::string longer = bytes;
  longer.insert(40, "x");
  writePlain(garbled, longer);
  expectError([&] { readCheckpoint(garbled); }, {garbled.string(), "checksum"});
}

// FNV-1a, as the checkpoint writer hashes its bytes, to forge files whose hash is right but whose
// content is not: the reader must not rely on the hash alone.
std::string withHash(std::string bytes) {
  bytes.resize(bytes.size() - 8);
  uint64_t hash = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    hash ^= uint8_t(c);
    hash *= 0x100000001b3ull;
  }
  for (int i = 0; i < 8; ++i) bytes.push_back(char(hash >> (8 * i)));
  return bytes;
}

void putU64(std::string& bytes, size_t offset, uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes[offset + size_t(i)] = char(value >> (8 * i));
}

TEST_F(RunFiles, InconsistentCheckpointsAreRejectedEvenWithAValidHash) {
  writeCheckpoint(m_dir / "full.bin", sample());
  const std::string bytes = readAll(m_dir / "full.bin");
  // Layout: magic 0-7, version 8-11, iteration 12, seconds 20, steps 28, adjoint scale 36, counts
  // from 44: parameters, first, second, bvh, losses; the first name's length at 84.
  struct Forgery {
    const char* expected;
    std::function<void(std::string&)> edit;
  };
  const Forgery forgeries[] = {
      {"unsupported checkpoint version 3", [](std::string& b) { b[8] = 3; }},
      {"mismatched sizes: 3 second moments for 4 parameters", [](std::string& b) { putU64(b, 60, 3); }},
      {"mismatched sizes: 3 first moments for 4 parameters", [](std::string& b) { putU64(b, 52, 3); }},
      {"mismatched sizes: 2 BVH parameters for 4 parameters", [](std::string& b) { putU64(b, 68, 2); }},
      {"parameter names do not fit",
       [](std::string& b) {
         for (size_t offset : {44, 52, 60, 68}) putU64(b, offset, uint64_t(1) << 60);
       }},
      {"initial losses: 1152921504606846976 values do not fit", [](std::string& b) { putU64(b, 76, uint64_t(1) << 60); }},
      {"unexpected bytes after the last field", [](std::string& b) { putU64(b, 76, 1); }},
      {"invalid name", [](std::string& b) { b[88] = ','; }},
      {"truncated", [](std::string& b) { b[84] = char(200); }},
      {"not a finite, non-negative number", [](std::string& b) { putU64(b, 20, 0xfff0000000000000ull); }},
      {"adjoint scale", [](std::string& b) { putU64(b, 36, 0x7ff8000000000000ull); }},
  };
  const fs::path forged = m_dir / "forged.bin";
  for (const Forgery& f : forgeries) {
    std::string copy = bytes;
    f.edit(copy);
    writePlain(forged, withHash(copy));
    expectError([&] { readCheckpoint(forged); }, {forged.string(), f.expected});
  }
}

TEST_F(RunFiles, MissingOrForeignFilesAreRejected) {
  expectError([&] { readCheckpoint(m_dir / "absent.bin"); }, {(m_dir / "absent.bin").string(), "file not found"});
  writePlain(m_dir / "log.csv", "iteration,loss\n0,1\n1,0.5\n2,0.25\n");
  expectError([&] { readCheckpoint(m_dir / "log.csv"); }, {(m_dir / "log.csv").string(), "not a vktg checkpoint"});
}

TEST_F(RunFiles, InconsistentCheckpointsAreNotWritten) {
  Checkpoint c = sample();
  c.names.pop_back();
  expectError([&] { writeCheckpoint(m_dir / "c.bin", c); }, {"c.bin", "3 names for 4 parameters"});
  c = sample();
  c.optimizer.second.resize(2);
  expectError([&] { writeCheckpoint(m_dir / "c.bin", c); }, {"2 second moments for 4 parameters"});
  EXPECT_FALSE(fs::exists(m_dir / "c.bin"));
}

TEST_F(RunFiles, CheckpointMustMatchTheExperiment) {
  const Experiment x = loadExperiment(kData / "complete.json");  // h0-h15, grey, t0; two targets
  Checkpoint c;
  for (const ExperimentParameter& p : x.parameters) c.names.push_back(p.name);
  c.initialLoss = {1, 2};
  const fs::path path = m_dir / "c.bin";
  checkCheckpointMatches(path, c, x);
  Checkpoint swapped = c;
  std::swap(swapped.names[16], swapped.names[17]);
  expectError([&] { checkCheckpointMatches(path, swapped, x); },
              {path.string(), "parameter 16 is \"t0\" there and \"grey\" in the experiment"});
  Checkpoint fewer = c;
  fewer.names.pop_back();
  expectError([&] { checkCheckpointMatches(path, fewer, x); }, {"written for 17 parameters", "optimises 18"});
  Checkpoint oneTarget = c;
  oneTarget.initialLoss = {1};
  expectError([&] { checkCheckpointMatches(path, oneTarget, x); }, {"initial losses of 1 targets", "has 2"});
  // Stopped during its first iteration: no loss yet, which is only valid at iteration 0.
  Checkpoint first = c;
  first.initialLoss.clear();
  checkCheckpointMatches(path, first, x);
  first.iteration = 1;
  expectError([&] { checkCheckpointMatches(path, first, x); }, {"initial losses of 0 targets", "has 2"});
}

TEST_F(RunFiles, LogWritesAHeaderAndExactRows) {
  const fs::path path = m_dir / "log.csv";
  writePlain(path, "left over from an earlier run\n");
  RunLog log(path, {"iteration", "loss", "seconds"}, false, 0);
  EXPECT_EQ(readAll(path), "iteration,loss,seconds\n");
  log.append({0, 0.1, 1.0 / 3.0});
  log.append({1, NAN, INFINITY});
  EXPECT_EQ(readAll(path), "iteration,loss,seconds\n0,0.10000000000000001,0.33333333333333331\n1,nan,inf\n");
  EXPECT_EQ(std::strtod("0.33333333333333331", nullptr), 1.0 / 3.0);  // 17 digits read back exactly
  expectError([&] { log.append({1, 2}); }, {path.string(), "a row of 2 values for 3 columns"});
}

TEST_F(RunFiles, ResumedLogKeepsTheRowsTheCheckpointCovers) {
  const fs::path path = m_dir / "log.csv";
  writePlain(path, "iteration,loss\n0,4\n1,3\n2,2\n3,1\n4,0.5");  // the last row was cut short
  {
    RunLog log(path, {"iteration", "loss"}, true, 2);
    log.append({2, 1.5});
  }
  EXPECT_EQ(readAll(path), "iteration,loss\n0,4\n1,3\n2,1.5\n");
  RunLog all(path, {"iteration", "loss"}, true, 3);
  EXPECT_EQ(readAll(path), "iteration,loss\n0,4\n1,3\n2,1.5\n");
  RunLog none(path, {"iteration", "loss"}, true, 0);
  EXPECT_EQ(readAll(path), "iteration,loss\n");
}

TEST_F(RunFiles, ResumedLogErrors) {
  const fs::path path = m_dir / "log.csv";
  expectError([&] { RunLog(path, {"iteration"}, true, 0); }, {path.string(), "file not found"});
  writePlain(path, "iteration,loss\n0,4\n1,3\n2");
  const std::string before = readAll(path);
  expectError([&] { RunLog(path, {"iteration", "loss"}, true, 3); }, {path.string(), "holds 2 complete rows", "covers 3"});
  expectError([&] { RunLog(path, {"iteration", "loss", "error"}, true, 1); },
              {path.string(), "header differs", "iteration,loss,error"});
  writePlain(path, "iteration,loss\n0,4\n1\n");
  expectError([&] { RunLog(path, {"iteration", "loss"}, true, 2); }, {path.string(), "line 3", "1 fields, expected 2"});
  writePlain(path, before);
  expectError([&] { RunLog(path, {"iteration", "loss,target"}, true, 1); }, {"column name \"loss,target\""});
  expectError([&] { RunLog(path, {}, false, 0); }, {"at least one column"});
  EXPECT_EQ(readAll(path), before);  // nothing rewritten by a failed open
}

// The optimised scene holds every optimised parameter of an expanding entry at its place in
// `values`, also when only some of the entry's parameters were optimised, and loads as the scene
// moved by θ.
TEST_F(RunFiles, OptimisedSceneWritesTheValuesOfExpandedParameters) {
  const nlohmann::json experiment = {{"version", 1},
                                     {"scene", "terrain_free.json"},
                                     {"parameters", {{{"name", "h7"}}, {{"name", "v5_*"}}}},
                                     {"targets", {{{"image", "front.exr"}}}}};
  const Experiment x = parseExperimentJson(experiment.dump(), "free.experiment.json", kData);
  ASSERT_EQ(x.parameters.size(), 4u);
  const std::vector<double> theta = {0.25, 0.125, -0.5, 0.0625};  // h7, v5_x, v5_y, v5_z
  ASSERT_TRUE(writeOptimizedScene(m_dir / "out.json", x, theta));
  const nlohmann::json written = nlohmann::json::parse(readAll(m_dir / "out.json"));
  EXPECT_EQ(written["parameters"][0]["values"].size(), 16u);
  EXPECT_EQ(written["parameters"][0]["values"][7], 0.25);
  EXPECT_EQ(written["parameters"][1]["values"].size(), 48u);
  EXPECT_EQ(written["parameters"][1]["values"][16], -0.5);
  const Scene moved = loadScene(m_dir / "out.json");
  const std::vector<glm::vec3>& before = x.scene.shapes[0].positions;
  const std::vector<glm::vec3>& after = moved.shapes[0].positions;
  ASSERT_EQ(after.size(), before.size());
  for (size_t v = 0; v < before.size(); ++v) {
    glm::vec3 expected = before[v];
    if (v == 7) expected.y += 0.25f;
    if (v == 5) expected += glm::vec3(0.125f, -0.5f, 0.0625f);
    EXPECT_NEAR(glm::distance(after[v], expected), 0.0f, 1e-6f) << "vertex " << v;
  }
}

}  // namespace
}  // namespace vktg

namespace vktg {
namespace {

// The loss figure of a scan (one target per scan point) draws the total and the regularisation, not
// 64 legend entries, which left no room for the axes and stopped the run at its first checkpoint.
class RunFilesFigures : public test::TempDirTest {};

TEST_F(RunFilesFigures, LossFigureOfManyTargetsFits) {
  for (size_t targets : {size_t(3), size_t(64)}) {
    Experiment e;
    std::map<std::string, std::vector<double>> log;
    for (int i = 0; i < 12; ++i) {
      log["iteration"].push_back(i);
      log["loss"].push_back(1.0 / (1 + i));
      log["regularization"].push_back(0.01 / (1 + i));
    }
    for (size_t t = 0; t < targets; ++t) {
      Target target;
      target.name = target.entryName = "scan_" + std::to_string(t);
      e.targets.push_back(target);
      log["loss_" + target.name] = std::vector<double>(12, 1.0 / double(targets));
    }
    const fs::path run = m_dir / std::to_string(targets);
    fs::create_directories(run);
    ASSERT_NO_THROW(writeRunFigures(run, e, log, {})) << targets << " targets";
    EXPECT_GT(fs::file_size(run / "loss.png"), 0u) << targets << " targets";
  }
}

}  // namespace
}  // namespace vktg
