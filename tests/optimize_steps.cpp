// The optimisation a step at a time (Optimization): a loop of evaluate and step written by its
// caller is the run `vktg optimize` makes, bit for bit; an evaluation repeats at the same θ and
// iteration; a step refuses an evaluation of another θ; and θ moves only in step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "optimize/optimize.h"
#include "opt/run_files.h"
#include "support/cli_runner.h"
#include "support/gpu_context.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

const fs::path kExperiment = fs::path(VKTG_TEST_DATA) / "optimize" / "converge_heightfield.json";
constexpr uint32_t kIterations = 2;

OptimizeOptions optionsFor(const fs::path& out) {
  OptimizeOptions o;
  o.experiment = kExperiment;
  o.runDirectory = out;
  o.iterations = kIterations;
  return o;
}

std::vector<std::string> rowsWithoutTime(const fs::path& log) {
  std::ifstream in(log);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(line.substr(0, line.rfind(',')));
  return rows;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(OptimizeSteps, ACallersLoopIsTheRunOptimizeMakes) {
  TempDir dir;
  const OptimizeSummary whole = optimize(test::testContext(), optionsFor(dir / "whole"));

  Optimization run(test::testContext(), optionsFor(dir / "steps"));
  ASSERT_EQ(run.parameterNames().size(), run.theta().size());
  EXPECT_EQ(run.iteration(), 0u);
  EXPECT_FALSE(run.stopped());
  while (!run.stopped()) {
    const std::vector<double> before = run.theta();
    const Evaluation evaluation = run.evaluate();
    EXPECT_EQ(evaluation.iteration, run.iteration());
    EXPECT_TRUE(sameBits(run.theta(), before)) << "evaluate moved θ";
    ASSERT_EQ(evaluation.gradient.theta.size(), before.size());
    ASSERT_EQ(evaluation.targetLosses.size(), evaluation.images.size());
    EXPECT_TRUE(std::isfinite(evaluation.loss) && evaluation.loss > 0);
    if (run.iteration() == 0) {
      // The same iteration's random numbers at the same θ: the same loss and gradient.
      const Evaluation again = run.evaluate();
      EXPECT_EQ(again.loss, evaluation.loss);
      EXPECT_TRUE(sameBits(again.gradient.theta, evaluation.gradient.theta)) << "a repeated evaluation differs";
    }
    run.step(evaluation);
    EXPECT_FALSE(sameBits(run.theta(), before)) << "step left θ where it was";
    // An evaluation is of one iteration and θ: stepping with it again is refused.
    if (!run.stopped()) EXPECT_THROW(run.step(evaluation), Error);
  }
  const OptimizeSummary steps = run.finish();
  EXPECT_EQ(steps.iterations, whole.iterations);
  EXPECT_EQ(steps.stopReason, whole.stopReason);
  EXPECT_EQ(steps.loss, whole.loss);
  EXPECT_EQ(rowsWithoutTime(dir / "steps" / "log.csv"), rowsWithoutTime(dir / "whole" / "log.csv"));
  EXPECT_TRUE(sameBits(readCheckpoint(dir / "steps" / "checkpoint.bin").theta,
                       readCheckpoint(dir / "whole" / "checkpoint.bin").theta));
  EXPECT_EQ(test::readFileBytes(dir / "steps" / "parameters.json"), test::readFileBytes(dir / "whole" / "parameters.json"));
}

}  // namespace
}  // namespace vktg
