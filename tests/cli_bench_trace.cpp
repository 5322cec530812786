// `vktg bench trace` measures the traversal the renderer uses: its rays must get the host
// traversal's answers (the benchmark checks 4096 per point and reports disagreements), and with an
// unbounded tMax a ray has an any hit exactly when it has a closest hit. Speed is the benchmark's
// output, never asserted here.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.h"

namespace vktg::test {
namespace {

// bench.csv rows as column name -> value (the scene column is quoted and holds commas).
std::vector<std::map<std::string, std::string>> readCsv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(std::exchange(cell, {}));
      else cell += c;
    }
    cells.push_back(cell);
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < names.size() && i < cells.size(); ++i) row[names[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

TEST(CliBenchTrace, DeviceRaysAgreeWithTheHostTraversal) {
  TempDir dir;
  CliResult r = runVktg({"bench", "trace", "--scale", "0.01", "--runs", "1", "--sizes", "33", "--no-embree", "--out",
                         (dir / "bench").string()});
  ASSERT_EQ(r.exitCode, 0) << r.describe();
  const auto rows = readCsv(readFileBytes(dir / "bench" / "bench.csv"));
  ASSERT_EQ(rows.size(), 8u) << "2 scenes x 2 ray kinds x 2 queries";
  std::map<std::string, std::string> closestHits;
  for (const auto& row : rows) {
    const std::string what = row.at("scene") + ", " + row.at("rays") + ", " + row.at("query");
    EXPECT_GT(std::stod(row.at("rays_per_second")), 0.0) << what;
    EXPECT_EQ(row.at("checked"), "4096") << what;
    EXPECT_EQ(row.at("disagreements"), "0") << what;
    EXPECT_TRUE(row.at("tree") == "4-wide" || row.at("tree") == "binary") << what << ": tree " << row.at("tree");
    const double hits = std::stod(row.at("hit_fraction"));
    EXPECT_GT(hits, 0.5) << what << ": the rays should mostly hit the room";
    const std::string key = row.at("scene") + "/" + row.at("rays");
    if (row.at("query") == "closest") closestHits[key] = row.at("hit_fraction");
    else EXPECT_EQ(row.at("hit_fraction"), closestHits.at(key)) << what << ": any hit and closest hit disagree";
  }
  EXPECT_NE(readFileBytes(dir / "bench" / "table.md").find("| room, 33x33 heightfield | 2060 |"), std::string::npos);
}

}  // namespace
}  // namespace vktg::test
