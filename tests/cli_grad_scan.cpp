// End-to-end tests of `vktg grad --scan` and `vktg fd --scan`: the derivative images of every view of
// a scan come from renders that hold all the views, laid out as `vktg render --scan` lays out the
// scan's image, and each view's derivatives are bit for bit those of the one-view command at that
// point (its sensor and laser moved there, its seed the scan's derived seed), for every term.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "scene/seeds.h"
#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kScene = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan" / "scene.json";
constexpr uint32_t kSeed = 11;

// A 2 x 2 grid of confocal points on the relay wall (y = 1), the laser at each.
json gridScan() {
  return {{"version", 1},
          {"grid",
           {{"corner", {-0.2, 1.0, -0.2}}, {"across", {0.4, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.4}},
            {"resolution", {2, 2}}, {"lights", {"laser"}}}}};
}

// The scene as seen from grid point k alone, and the options that render it as the scan's view k.
std::vector<std::string> onePointArgs(const std::vector<std::string>& command, uint32_t k, const TempDir& dir) {
  json scene;
  std::ifstream(kScene) >> scene;
  const json point = {-0.2 + 0.4 * (k % 2), 1.0, -0.2 + 0.4 * (k / 2)};
  scene["camera"]["position"] = point;
  scene["lights"][0]["position"] = point;
  writeJsonFile(dir / "point.json", scene);
  std::vector<std::string> args = command;
  args.insert(args.begin() + 1, (dir / "point.json").string());
  args[std::find(args.begin(), args.end(), "--seed") - args.begin() + 1] =
      std::to_string(derivedSeed((uint64_t(kSeed) << 32) ^ k));
  return args;
}

// One layer file of a run (relative to its run folder) and whether some of its pixels must be non-zero.
struct LayerFile {
  std::string suffix;
  bool expectNonZero;
};

// Runs `command` (its scene inserted as the first argument) on the scan and at points 0 and 3 alone,
// and compares every layer of each file pixel by pixel.
void expectScanPixelsAreTheOnePointImages(const std::vector<std::string>& command, const std::vector<LayerFile>& files) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", gridScan());
  std::vector<std::string> scanArgs = command;
  scanArgs.insert(scanArgs.begin() + 1, kScene.string());
  for (const std::string& a : {std::string("--scan"), (dir / "scan.json").string(), std::string("--out"), (dir / "scan.exr").string()})
    scanArgs.push_back(a);
  runVktgOk(scanArgs, dir);
  std::vector<ImageSet> scans;
  for (const LayerFile& file : files) {
    scans.push_back(readExr(dir / ("scan" + file.suffix)));
    ASSERT_EQ(scans.back().width, 2u) << file.suffix;
    ASSERT_EQ(scans.back().height, 2u) << file.suffix;
    ASSERT_FALSE(scans.back().layers.empty()) << file.suffix;
  }
  std::vector<double> magnitudes(files.size(), 0.0);
  for (uint32_t k : {0u, 3u}) {
    std::vector<std::string> one = onePointArgs(command, k, dir);
    one.push_back("--out");
    one.push_back((dir / "point.exr").string());
    runVktgOk(one, dir);
    for (size_t f = 0; f < files.size(); ++f) {
      const ImageSet alone = readExr(dir / ("point" + files[f].suffix));
      const ImageSet& scan = scans[f];
      ASSERT_EQ(alone.width * alone.height, 1u) << files[f].suffix;
      ASSERT_EQ(alone.layers.size(), scan.layers.size()) << files[f].suffix;
      for (size_t l = 0; l < alone.layers.size(); ++l) {
        EXPECT_EQ(scan.layers[l].name, alone.layers[l].name);
        EXPECT_EQ(scan.layers[l].pixels[k], alone.layers[l].pixels[0])
            << files[f].suffix << ", point " << k << ", layer " << scan.layers[l].name;
        magnitudes[f] += std::abs(alone.layers[l].pixels[0]);
      }
    }
  }
  for (size_t f = 0; f < files.size(); ++f)
    if (files[f].expectNonZero)
      EXPECT_GT(magnitudes[f], 0) << files[f].suffix << ": the heights below the points change their transients";
}

const std::vector<std::string> kCommon = {"--spp", "256", "--seed", std::to_string(kSeed), "--nee", "standard"};

std::vector<std::string> command(std::vector<std::string> head) {
  head.insert(head.end(), kCommon.begin(), kCommon.end());
  return head;
}

TEST(CliGradScan, EveryTermOfAViewIsTheOnePointDerivative) {
  // h27 and h36 lie under the middle of the hidden surface, seen from every point of the grid.
  const std::vector<std::string> grad = command({"grad", "--param", "h27,h36", "--split-terms"});
  // At a point sensor the first hit is a material point, so a border's own motion is the interior
  // term's and only what a silhouette uncovers behind it is the edge term's: nothing, here (zeros,
  // but the same ones).
  expectScanPixelsAreTheOnePointImages(
      grad, {{".exr", true}, {".interior.exr", true}, {".edge.exr", false}, {".pathlength.exr", true}});
}

TEST(CliGradScan, FiniteDifferencesOfAViewAreTheOnePointOnes) {
  expectScanPixelsAreTheOnePointImages(command({"fd", "--param", "h27", "--eps", "0.01"}), {{".exr", true}});
}

TEST(CliGradScan, AScanFileThatIsNoScanNamesItsFieldAndWritesNothing) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", {{"version", 1}, {"grid", {{"corner", {0, 1, 0}}}}});
  const CliResult r = runVktg({"grad", kScene.string(), "--param", "h27", "--scan", (dir / "scan.json").string(), "--out",
                               (dir / "g.exr").string()},
                              {.cwd = dir.path()});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("scan.json"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("grid"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir / "g.exr"));
}

}  // namespace
}  // namespace vktg::test
