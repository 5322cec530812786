// `vktg bench optimize` at toy sizes: a row per heightfield with every time measured, and with
// --profile the device time of every pass of the render and of each gradient variant, named by
// term (what docs/benchmarks.md's breakdown of a loss gradient is read from), and the term pilot's
// counts with all terms and an iteration at them, also with chained interior passes. Speed is the
// benchmark's output, never asserted here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_optimize.h"
#include "plan/term_allocation.h"
#include "support/cli_runner.h"
#include "support/gpu_context.h"

namespace vktg::test {
namespace {

TEST(CliBenchOptimize, EveryRowTimedAndEveryPassProfiled) {
  TempDir dir;
  CliResult r = runVktg({"bench", "optimize", "--sizes", "3,4", "--runs", "1", "--scale", "0.125", "--profile",
                         "--interior-passes", "2", "--out", (dir / "bench").string()});
  ASSERT_EQ(r.exitCode, 0) << r.describe();
  std::istringstream csv(readFileBytes(dir / "bench" / "bench.csv"));
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line.rfind("size,parameters,triangles,", 0), 0u) << line;
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 2u);
  for (const std::string& row : rows) {
    std::vector<double> cells;
    std::istringstream in(row);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(std::stod(cell));
    ASSERT_EQ(cells.size(), 26u) << row;
    // Every time, and the chained iteration's (2 passes of 1 sample after a render of 1) with its
    // two variance ratios.
    for (size_t c = 6; c <= 23; ++c) EXPECT_TRUE(std::isfinite(cells[c]) && cells[c] > 0) << row << ": column " << c;
    // The term pilot's counts (edges, boundary, its connections from the camera): at least
    // kTermPilotMinSpp per pixel, at most kTermPilotMaxFactor times the render's 2.
    for (size_t c : {13, 14, 15})
      EXPECT_TRUE(cells[c] >= kTermPilotMinSpp && cells[c] <= kTermPilotMaxFactor * 2) << row << ": column " << c;
  }
  const std::string log = r.out + r.err;
  // Keyed by the terms' names (plan/terms.h).
  for (const char* pass : {"render: ", "interior/shade_adj", "edge/sample_edges", "pathlength/shade_adj",
                           "pathlength-camera/connect_camera_boundary_adj", "interior+pathlength/shade_adj",
                           "interior/accumulate"})
    EXPECT_NE(log.find(pass), std::string::npos) << "no " << pass << " in the profile\n" << log;
}

// The report is handed over after every size, so a run stopped part-way (a time limit, Ctrl-C)
// keeps the rows it measured: here the second size never finishes, and the rows written are the
// first one's.
TEST(CliBenchOptimize, RowsAreHandedOverAsTheyAreMeasured) {
  TempDir dir;
  BenchOptimizeOptions options;
  options.sizes = {3, 4};
  options.runs = 1;
  options.scale = 0.125;
  options.outDir = dir / "bench";
  struct Stop {};
  std::vector<size_t> seen;
  EXPECT_THROW(benchOptimize(testContext(), options,
                             [&](const BenchOptimizeReport& report) {
                               seen.push_back(report.rows.size());
                               writeBenchOptimizeReport(report, options, "test");
                               throw Stop{};  // as an interrupt during the next size would
                             }),
               Stop);
  EXPECT_EQ(seen, std::vector<size_t>{1});
  const std::string csv = readFileBytes(dir / "bench" / "bench.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2) << csv;  // the header and the 3 x 3 row
  EXPECT_EQ(csv.find("\n3,9,"), csv.find('\n')) << csv;
}

// --positions: every vertex's x, y and z are parameters (a vertex_positions entry), three per vertex,
// and every term's gradient with respect to all of them is timed.
TEST(CliBenchOptimize, PositionsAreThreeParametersPerVertex) {
  TempDir dir;
  BenchOptimizeOptions options;
  options.sizes = {3};
  options.runs = 1;
  options.scale = 0.125;
  options.interiorPasses = 1;
  options.positions = true;
  options.outDir = dir / "bench";
  const BenchOptimizeReport report = benchOptimize(testContext(), options);
  ASSERT_EQ(report.rows.size(), 1u);
  const BenchOptimizeRow& row = report.rows[0];
  EXPECT_EQ(row.parameters, 27u);
  for (double seconds : {row.renderSeconds, row.interiorSeconds, row.edgeSeconds, row.boundarySeconds, row.allSeconds,
                         row.pilotAllSeconds, row.denseSeconds})
    EXPECT_TRUE(std::isfinite(seconds) && seconds > 0) << seconds;
  EXPECT_EQ(row.denseLanes, 8u);
}

}  // namespace
}  // namespace vktg::test
