// `vktg render --scan SCAN --out FILE.hdf5` (docs/scene-format.md, "NLOS captures (HDF5)"): the
// scan's transients in tal's layout, H the same values the EXR of the same render holds, the grids
// the scan's points; scenes and scans that make no capture are errors naming --out, and a failed
// run leaves an existing file as it was.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "io/nlos_capture.h"
#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kScene = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan" / "scene.json";
const std::vector<std::string> kCommon = {"--spp", "16", "--seed", "5", "--nee", "standard"};

// 3 x 2 points of the relay wall (y = 1), with the laser at each unless `lights` is empty.
json wallScan(const json& lights) {
  json grid = {{"corner", {-0.3, 1.0, -0.2}}, {"across", {0.6, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.4}}, {"resolution", {3, 2}}};
  if (!lights.empty()) grid["lights"] = lights;
  return {{"version", 1}, {"grid", grid}};
}

// Grid point (i, j) as the scan computes it.
glm::vec3 wallPoint(uint32_t i, uint32_t j) {
  glm::vec3 p(-0.3f, 1.0f, -0.2f);
  p += glm::vec3(0.6f, 0.0f, 0.0f) * (float(i) / float(2));
  p += glm::vec3(0.0f, 0.0f, 0.4f) * (float(j) / float(1));
  return p;
}

CliResult render(const TempDir& dir, const std::string& out, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"render", kScene.string(), "--scan", (dir / "scan.json").string(), "--out", (dir / out).string()};
  args.insert(args.end(), kCommon.begin(), kCommon.end());
  args.insert(args.end(), extra.begin(), extra.end());
  return runVktgOk(args, dir);
}

TEST(CliRenderCapture, ConfocalScanWritesTheExrsTransientsAndTheScanGrid) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", wallScan({"laser"}));
  render(dir, "scan.exr");
  const CliResult r = render(dir, "scan.hdf5");
  EXPECT_NE(r.err.find("wrote " + (dir / "scan.hdf5").string() + " and " + (dir / "scan.png").string()), std::string::npos)
      << r.describe();
  EXPECT_FALSE(fs::exists(dir / "scan.npy"));
  const ImageSet exr = readExr(dir / "scan.exr");
  const Capture c = readCapture(dir / "scan.hdf5");
  EXPECT_EQ(c.hFormat, CaptureHFormat::T_Sx_Sy);
  ASSERT_EQ(c.dims, (std::vector<uint32_t>{20, 3, 2})) << "(T, Sx, Sy): the scene's 20 bins, 3 columns, 2 rows";
  double total = 0;
  for (uint32_t t = 0; t < 20; ++t)
    for (uint32_t i = 0; i < 3; ++i)
      for (uint32_t j = 0; j < 2; ++j) {
        EXPECT_EQ(c.H[(t * 3 + i) * 2 + j], exr.layers[t].pixels[j * 3 + i]) << "bin " << t << ", point (" << i << ", " << j << ")";
        total += c.H[(t * 3 + i) * 2 + j];
      }
  EXPECT_GT(total, 0) << "the hidden surface returns light";
  for (uint32_t i = 0; i < 3; ++i)
    for (uint32_t j = 0; j < 2; ++j) {
      EXPECT_EQ(c.sensor.positions[i * 2 + j], wallPoint(i, j));
      EXPECT_EQ(c.laser.positions[i * 2 + j], wallPoint(i, j));
      EXPECT_EQ(c.sensor.normals[i * 2 + j], glm::vec3(0, -1, 0)) << "the scene's sensor normal";
    }
  EXPECT_TRUE(c.confocal);
  EXPECT_EQ(c.tStart, 1.6);
  EXPECT_EQ(c.deltaT, 0.05);
  EXPECT_FALSE(c.tAccountsFirstAndLastBounces);
  EXPECT_EQ(c.sensorXyz, glm::vec3(0, 1, 0)) << "the scene's sensor";
  EXPECT_NE(c.sceneInfo.find("\"generator\":\"vktg render\""), std::string::npos) << c.sceneInfo;
  // --npy still writes the cube beside it; .h5 is a capture too.
  render(dir, "scan.h5", {"--npy"});
  EXPECT_TRUE(fs::exists(dir / "scan.npy"));
  EXPECT_EQ(readCapture(dir / "scan.h5").H, c.H);
}

TEST(CliRenderCapture, AFixedLaserIsOnePointAndAListOfViewsIsAList) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", wallScan(json::array()));
  render(dir, "fixed.hdf5");
  const Capture fixed = readCapture(dir / "fixed.hdf5");
  EXPECT_FALSE(fixed.confocal);
  EXPECT_EQ(fixed.laser.shape, (std::vector<uint32_t>{1, 1}));
  EXPECT_EQ(fixed.laser.positions[0], glm::vec3(0, 1, 0)) << "the scene's light";

  writeJsonFile(dir / "scan.json", {{"version", 1},
                                    {"views",
                                     {{{"position", {0.1, 1.0, 0.0}}, {"lights", {{"laser", {0.1, 1.0, 0.0}}}}},
                                      {{"position", {0.2, 1.0, 0.1}}, {"lights", {{"laser", {0.2, 1.0, 0.1}}}}}}}});
  render(dir, "list.hdf5");
  const Capture list = readCapture(dir / "list.hdf5");
  EXPECT_EQ(list.hFormat, CaptureHFormat::T_Si);
  EXPECT_EQ(list.dims, (std::vector<uint32_t>{20, 2}));
  EXPECT_EQ(list.sensor.positions[1], glm::vec3(0.2f, 1.0f, 0.1f));
  EXPECT_TRUE(list.confocal);
}

TEST(CliRenderCapture, ScenesThatMakeNoCaptureNameOutAndLeaveTheFile) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", wallScan({"laser"}));
  writeFileBytes(dir / "out.hdf5", "previous");
  const std::string out = (dir / "out.hdf5").string();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"render", kScene.string(), "--out", out}, "give --scan"},
      {{"render", kScene.string(), "--scan", (dir / "scan.json").string(), "--gate", "box:1.6,2.6", "--out", out},
       "the scene's gate is box [1.6 m, 2.6 m]"},
      {{"render", "--scan", (dir / "views.json").string(), "--out", out}, "the scene's camera is a pinhole"},
  };
  writeJsonFile(dir / "views.json", {{"version", 1}, {"views", {{{"position", {0.0, 1.0, 3.4}}}}}});
  for (const Case& c : cases) {
    const CliResult r = runVktg(c.args, {.cwd = dir.path()});
    EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
    EXPECT_NE(r.err.find("--out: " + out + ": "), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.describe();
    EXPECT_EQ(readFileBytes(dir / "out.hdf5"), "previous");
    EXPECT_FALSE(fs::exists(dir / "out.png"));
  }
}

}  // namespace
}  // namespace vktg::test
