// End-to-end tests of `vktg render --scan` (docs/scene-format.md, "Scans"): a grid of confocal scan
// points on the relay wall of the confocal-scan experiment renders as one image of the grid, each
// pixel's transient bit for bit the one-view render of that point (its camera and laser moved there,
// its seed the scan's derived seed); a list of pinhole views stacks their images; the cube is what
// an experiment's scan target reads; bad scan files are errors naming the file and the field, with
// nothing written.
#include <gtest/gtest.h>

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
constexpr uint32_t kSeed = 7;

json readJson(const fs::path& path) {
  std::ifstream stream(path);
  return json::parse(stream);
}

TEST(CliRenderScan, GridPixelsAreTheOneViewRendersOfTheirPoints) {
  TempDir dir;
  // 3 x 2 points over part of the wall (y = 1), the laser at each.
  const json scan = {{"version", 1},
                     {"grid",
                      {{"corner", {-0.3, 1.0, -0.2}}, {"across", {0.6, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.4}},
                       {"resolution", {3, 2}}, {"lights", {"laser"}}}}};
  writeJsonFile(dir / "scan.json", scan);
  const std::vector<std::string> common = {"--spp", "16", "--seed", std::to_string(kSeed), "--nee", "standard"};
  std::vector<std::string> args = {"render", kScene.string(), "--scan", (dir / "scan.json").string(), "--npy",
                                   "--out", (dir / "scan.exr").string()};
  args.insert(args.end(), common.begin(), common.end());
  const CliResult r = runVktgOk(args, dir);
  EXPECT_NE(r.err.find("6 scan views (3 x 2) in one render"), std::string::npos) << r.describe();
  const ImageSet image = readExr(dir / "scan.exr");
  ASSERT_EQ(image.width, 3u);
  ASSERT_EQ(image.height, 2u);
  ASSERT_EQ(image.layers.size(), 20u) << "the scene's bins";
  EXPECT_TRUE(fs::exists(dir / "scan.npy"));

  // Point (i, j) alone: the scene with its sensor and laser at the point, the view's seed.
  const json scene = readJson(kScene);
  double total = 0;
  for (uint32_t k : {0u, 4u}) {
    const uint32_t i = k % 3, j = k / 3;
    const json point = {-0.3 + 0.3 * i, 1.0, -0.2 + 0.4 * j};
    json moved = scene;
    moved["camera"]["position"] = point;
    moved["lights"][0]["position"] = point;
    // Heights and materials as the original's (its folder holds nothing else it needs).
    writeJsonFile(dir / "point.json", moved);
    std::vector<std::string> one = {"render", (dir / "point.json").string(), "--out", (dir / "point.exr").string()};
    one.insert(one.end(), common.begin(), common.end());
    one[std::find(one.begin(), one.end(), "--seed") - one.begin() + 1] =
        std::to_string(derivedSeed((uint64_t(kSeed) << 32) ^ k));
    runVktgOk(one, dir);
    const ImageSet alone = readExr(dir / "point.exr");
    ASSERT_EQ(alone.width * alone.height, 1u);
    ASSERT_EQ(alone.layers.size(), image.layers.size());
    for (size_t b = 0; b < alone.layers.size(); ++b) {
      EXPECT_EQ(image.layers[b].pixels[j * 3 + i], alone.layers[b].pixels[0]) << "point " << k << ", bin " << b;
      total += alone.layers[b].pixels[0];
    }
  }
  EXPECT_GT(total, 0) << "the hidden surface returns light to the wall";
}

TEST(CliRenderScan, PinholeViewsStackTheirImages) {
  TempDir dir;
  writeJsonFile(dir / "views.json", {{"version", 1},
                                 {"views", {{{"position", {0.0, 1.0, 3.4}}}, {{"position", {0.5, 1.0, 3.4}}}}}});
  runVktgOk({"render", "--scan", (dir / "views.json").string(), "--spp", "2", "--resolution", "8x6", "--out",
         (dir / "views.exr").string()},
        dir);
  const ImageSet image = readExr(dir / "views.exr");
  EXPECT_EQ(image.width, 8u);
  EXPECT_EQ(image.height, 12u) << "two 8 x 6 views, one below the other";
}

TEST(CliRenderScan, ARenderedScanIsAnOptimisationTarget) {
  // The cube `vktg render --scan` writes is what a scan target of an experiment reads: the hidden
  // heights start flat and are fitted to it for two iterations (the plumbing, not convergence).
  TempDir dir;
  fs::copy_file(kScene, dir / "scene.json");
  writeJsonFile(dir / "scan.json", {{"version", 1},
                                {"grid",
                                 {{"corner", {-0.3, 1.0, -0.3}}, {"across", {0.6, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.6}},
                                  {"resolution", {3, 3}}, {"lights", {"laser"}}}}});
  runVktgOk({"render", "scene.json", "--scan", "scan.json", "--spp", "1024", "--out", "cube.exr"}, dir);
  writeJsonFile(dir / "experiment.json", {{"version", 1},
                                      {"scene", "scene.json"},
                                      {"parameters", {{{"name", "h*"}, {"initial", 0}}}},
                                      {"targets", {{{"name", "wall"}, {"scan", "scan.json"}, {"image", "cube.exr"}}}},
                                      {"render", {{"spp", 16}}},
                                      {"stop", {{"iterations", 2}}}});
  const CliResult r = runVktgOk({"optimize", "experiment.json", "--out", "run"}, dir);
  // The scan is one entry of the log and of the images: its points' losses summed in one column,
  // its first renders in one cube laid out as the target's.
  const std::string log = readFileBytes(dir / "run" / "log.csv");
  EXPECT_EQ(log.substr(0, log.find('\n')), "iteration,loss,loss_wall,gradient_norm,seconds");
  const ImageSet initial = readExr(dir / "run" / "images" / "wall_initial.exr");
  const ImageSet target = readExr(dir / "cube.exr");
  EXPECT_EQ(initial.width, target.width);
  EXPECT_EQ(initial.height, target.height);
  EXPECT_EQ(initial.layers.size(), target.layers.size());
  EXPECT_FALSE(fs::exists(dir / "run" / "images" / "wall_0_0_initial.exr"));
  EXPECT_TRUE(fs::exists(dir / "run" / "images" / "transients" / "1.png")) << r.describe();
  // A resumed run splits the cube back into its points for the figures.
  fs::remove(dir / "run" / "images" / "transients" / "2.png");
  const CliResult resumed = runVktgOk({"optimize", "--resume", "run", "--iterations", "3"}, dir);
  EXPECT_TRUE(fs::exists(dir / "run" / "images" / "transients" / "2.png")) << resumed.describe();
}

TEST(CliRenderScan, BadScanFilesNameTheFieldAndWriteNothing) {
  TempDir dir;
  writeJsonFile(dir / "bad.json", {{"version", 1}, {"grid", {{"corner", {0, 1, 0}}, {"resolution", {2, 2}}}}});
  const CliResult r = runVktg({"render", kScene.string(), "--scan", (dir / "bad.json").string(), "--out",
                               (dir / "out.exr").string()},
                              {.cwd = dir.path()});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find((dir / "bad.json").string()), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("grid.across"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
  const CliResult missing = runVktg({"render", kScene.string(), "--scan", (dir / "none.json").string()}, {.cwd = dir.path()});
  EXPECT_TRUE(missing.exited && missing.exitCode != 0) << missing.describe();
  EXPECT_NE(missing.err.find("none.json"), std::string::npos) << missing.describe();
}

}  // namespace
}  // namespace vktg::test
