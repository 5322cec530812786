// `vktg bench pilot` at a tiny scale: every case gets a prediction and a measurement for all three
// estimators, positive and finite, and a summary row naming the pilot's and the rule's choices with
// regrets >= 1 (1 for the measured best itself). Whether the predictions are good is the
// benchmark's output (docs/benchmarks.md), never asserted here.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.h"

namespace vktg::test {
namespace {

std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream cellsIn(line);
    for (std::string cell; std::getline(cellsIn, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(CliBenchPilot, EveryCaseHasPredictionsMeasurementsAndChoices) {
  TempDir dir;
  CliResult r = runVktg({"bench", "pilot", "--scale", "0.05", "--runs", "2", "--out", (dir / "bench").string()});
  ASSERT_EQ(r.exitCode, 0) << r.describe();
  const auto rows = csvRows(readFileBytes(dir / "bench" / "bench.csv"));
  ASSERT_EQ(rows.size(), 18u) << "6 cases x 3 estimators";
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 9u);
    const std::string what = row[0] + ", " + row[1] + ", " + row[2];
    EXPECT_TRUE(row[2] == "standard" || row[2] == "ellipsoidal" || row[2] == "mis") << what;
    for (int column : {4, 5, 6, 7}) {
      const double v = std::stod(row[column]);
      EXPECT_TRUE(std::isfinite(v) && v > 0) << what << ": column " << column << " = " << row[column];
    }
  }
  const std::string table = readFileBytes(dir / "bench" / "table.md");
  size_t summaries = 0;
  for (size_t at = table.find("\n| cornell | "); at != std::string::npos; at = table.find("\n| cornell | ", at + 1))
    ++summaries;
  EXPECT_EQ(summaries, 4u + 12u) << "4 Cornell summaries and 12 Cornell estimator rows\n" << table;
  EXPECT_NE(table.find("pilot's choice"), std::string::npos) << table;
}

TEST(CliBenchPilot, OneRunCannotMeasureAVarianceAndSaysSo) {
  TempDir dir;
  CliResult r = runVktg({"bench", "pilot", "--runs", "1", "--out", (dir / "bench").string()});
  EXPECT_NE(r.exitCode, 0) << r.describe();
  EXPECT_NE(r.err.find("--runs must be at least 2"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace vktg::test
