// `vktg render --scan SCAN --out FILE.hdf5` (docs/scene-format.md, "NLOS captures (HDF5)"): the
// scan's transients as a tal capture hold exactly the values the EXR of the same render holds, with
// the scan's points as the sensor grid and the bins gate's times; what cannot be a capture is an
// error naming --out, with nothing written.
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

json readJsonFile(const fs::path& path) {
  std::ifstream stream(path);
  return json::parse(stream);
}

json confocalGrid() {
  return {{"version", 1},
          {"grid",
           {{"corner", {-0.3, 1.0, -0.2}}, {"across", {0.6, 0.0, 0.0}}, {"down", {0.0, 0.0, 0.4}},
            {"resolution", {3, 2}}, {"lights", {"laser"}}}}};
}

TEST(CliRenderHdf5, ACaptureHoldsTheScanImageAndItsGrid) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", confocalGrid());
  auto render = [&](const std::string& out) {
    runVktgOk({"render", kScene.string(), "--scan", (dir / "scan.json").string(), "--spp", "16", "--seed", "3",
               "--out", (dir / out).string()},
              dir);
  };
  render("scan.exr");
  render("scan.hdf5");
  const ImageSet exr = readExr(dir / "scan.exr");
  const Capture capture = readCapture(dir / "scan.hdf5");
  EXPECT_EQ(capture.hFormat, CaptureHFormat::T_Sx_Sy);
  EXPECT_TRUE(capture.confocal);
  EXPECT_FALSE(capture.tAccountsFirstAndLastBounces);
  const ImageSet fromCapture = captureImage(capture);
  ASSERT_EQ(fromCapture.width, exr.width);
  ASSERT_EQ(fromCapture.height, exr.height);
  ASSERT_EQ(fromCapture.layers.size(), exr.layers.size());
  double total = 0;
  for (size_t l = 0; l < exr.layers.size(); ++l) {
    EXPECT_EQ(fromCapture.layers[l].pixels, exr.layers[l].pixels) << "bin " << l;
    for (float x : exr.layers[l].pixels) total += x;
  }
  EXPECT_GT(total, 0.0);  // light reached the wall: equal zeros would prove nothing
  // Sensor point (x, y) of the grid is scan point (i, j) = (x, y).
  ASSERT_EQ(capture.sensor.size(), 6u);
  for (uint32_t x = 0; x < 3; ++x)
    for (uint32_t y = 0; y < 2; ++y) {
      const glm::vec3 p = capture.sensor.positions[x * 2 + y];
      EXPECT_NEAR(p.x, -0.3 + 0.3 * x, 1e-6);
      EXPECT_NEAR(p.y, 1.0, 1e-6);
      EXPECT_NEAR(p.z, -0.2 + 0.4 * y, 1e-6);
    }
  const json scene = readJsonFile(kScene);
  EXPECT_NEAR(capture.tStart, scene["gate"]["start"].get<double>(), 1e-6);
  EXPECT_NEAR(capture.deltaT, scene["gate"]["width"].get<double>(), 1e-6);
}

TEST(CliRenderHdf5, WhatIsNoCaptureIsAnErrorAndWritesNothing) {
  TempDir dir;
  writeJsonFile(dir / "scan.json", confocalGrid());
  const fs::path out = dir / "scan.hdf5";
  const CliResult boxGate = runVktg({"render", kScene.string(), "--scan", (dir / "scan.json").string(), "--spp", "1",
                                     "--gate", "box:1.6,2.6", "--out", out.string()},
                                    {.cwd = dir.path()});
  EXPECT_TRUE(boxGate.exited && boxGate.exitCode != 0) << boxGate.describe();
  EXPECT_NE(boxGate.err.find("--out"), std::string::npos) << boxGate.describe();
  EXPECT_FALSE(fs::exists(out));
  const CliResult noScan = runVktg({"render", kScene.string(), "--spp", "1", "--out", out.string()}, {.cwd = dir.path()});
  EXPECT_TRUE(noScan.exited && noScan.exitCode != 0) << noScan.describe();
  EXPECT_NE(noScan.err.find("--out"), std::string::npos) << noScan.describe();
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace vktg::test
