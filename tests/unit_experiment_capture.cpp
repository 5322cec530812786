// Experiment targets from NLOS capture files (docs/optimize.md, "Captures"): the capture's sensor
// points become a scan's views (with its normals, the listed lights at its laser points, and the
// device legs as each view's path offset when its times count them), its bins the gate, its H the
// image; bad targets are errors naming the target's field and the file.
#include <hdf5.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "io/nlos_capture.h"
#include "opt/experiment.h"
#include "support/file_test.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::expectError;

const fs::path kScene = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan" / "scene.json";

// A 3 x 2 grid on the experiment's wall (y = 1) with 4 bins of 5 cm from 1.6 m; the laser device
// and the sensor beside each other 2 m above, and times that count the legs.
Capture wallCapture() {
  Capture c;
  c.hFormat = CaptureHFormat::T_Sx_Sy;
  c.dims = {4, 3, 2};
  for (int i = 0; i < 24; ++i) c.H.push_back(0.01f * float(i));
  c.sensor.shape = {3, 2};
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 2; ++y) {
      c.sensor.positions.push_back({-0.3f + 0.3f * x, 1.0f, -0.2f + 0.4f * y});
      c.sensor.normals.push_back({0.0f, -2.0f, 0.0f});  // normalised by the target
    }
  c.laser = c.sensor;
  c.confocal = true;
  c.sensorXyz = glm::vec3(0.5f, 3.0f, 0.0f);
  c.laserXyz = glm::vec3(-0.5f, 3.0f, 0.0f);
  c.deltaT = 0.05;
  c.tStart = 1.6;
  c.tAccountsFirstAndLastBounces = true;
  return c;
}

class ExperimentCaptureTest : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    fs::copy_file(kScene, m_dir / "scene.json");
  }
  // The experiment with `target` as its one target.
  Experiment parse(const json& target, const std::string& scene = "scene.json") {
    const json experiment = {{"version", 1},
                             {"scene", scene},
                             {"parameters", {{{"name", "h*"}}}},
                             {"targets", {target}}};
    return parseExperimentJson(experiment.dump(), (m_dir / "experiment.json").string(), m_dir);
  }
};

TEST_F(ExperimentCaptureTest, SensorPointsBecomeViewsAndTheLegsTheirPathOffsets) {
  const Capture capture = wallCapture();
  writeCaptureTal(m_dir / "wall.hdf5", capture);
  const Experiment e = parse({{"name", "wall"}, {"capture", "wall.hdf5"}, {"lights", {"laser"}}, {"weight", 2}});
  ASSERT_EQ(e.targets.size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    const Target& t = e.targets[k];
    const uint32_t x = uint32_t(k % 3), y = uint32_t(k / 3);
    EXPECT_EQ(t.name, "wall_" + std::to_string(x) + "_" + std::to_string(y));
    EXPECT_TRUE(t.capture);
    EXPECT_EQ(t.image, m_dir / "wall.hdf5");
    EXPECT_EQ(t.weight, 2);
    EXPECT_EQ(t.scanView, k);
    EXPECT_EQ(t.scanColumns, 3u);
    EXPECT_EQ(t.scanRows, 2u);
    const glm::vec3 s = capture.sensor.positions[x * 2 + y];
    EXPECT_EQ(t.view.position, s) << "view (x, y) is grid point (x, y)";
    EXPECT_EQ(t.view.normal, glm::vec3(0, -1, 0));
    ASSERT_EQ(t.view.lightPositions.size(), 1u);
    EXPECT_EQ(t.view.lightPositions[0].first, 0u);
    EXPECT_EQ(t.view.lightPositions[0].second, s) << "confocal: the laser at the sensor's point";
    const double legs = double(glm::length(*capture.sensorXyz - s)) + double(glm::length(*capture.laserXyz - s));
    EXPECT_EQ(t.view.pathOffset, float(legs));
    EXPECT_GT(t.view.pathOffset, 4.0f);
    EXPECT_EQ(t.gate.type, GateType::Bins);
    EXPECT_EQ(t.gate.binStart, 1.6);
    EXPECT_EQ(t.gate.binWidth, 0.05);
    EXPECT_EQ(t.gate.binCount, 4u);
  }
  // Each point's image is its transient: H[t, x, y] in layer t.
  const std::vector<TargetEntry> entries = targetEntries(e);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_TRUE(entries[0].scan);
  const std::vector<ImageSet> images = loadTargetImages(e, entries[0]);
  ASSERT_EQ(images.size(), 6u);
  const size_t k = 1 * 3 + 2;  // point (2, 1)
  ASSERT_EQ(images[k].layers.size(), 4u);
  for (uint32_t t = 0; t < 4; ++t) EXPECT_EQ(images[k].layers[t].pixels[0], capture.H[(t * 3 + 2) * 2 + 1]);

  // Times without the legs: no offset.
  Capture unwarped = capture;
  unwarped.tAccountsFirstAndLastBounces = false;
  writeCaptureTal(m_dir / "unwarped.hdf5", unwarped);
  const Experiment u = parse({{"name", "wall"}, {"capture", "unwarped.hdf5"}, {"lights", {"laser"}}});
  for (const Target& t : u.targets) EXPECT_EQ(t.view.pathOffset, 0.0f);
}

TEST_F(ExperimentCaptureTest, OneLaserPointLightsEveryView) {
  Capture capture = wallCapture();
  capture.laser.shape = {1, 1};
  capture.laser.positions = {{0.0f, 1.0f, 0.3f}};
  capture.laser.normals = {{0.0f, -1.0f, 0.0f}};
  capture.confocal = false;
  writeCaptureTal(m_dir / "single.hdf5", capture);
  const Experiment e = parse({{"capture", "single.hdf5"}, {"lights", {"laser"}}});
  ASSERT_EQ(e.targets.size(), 6u);
  for (const Target& t : e.targets) {
    EXPECT_EQ(t.view.lightPositions[0].second, glm::vec3(0.0f, 1.0f, 0.3f));
    const double legs = double(glm::length(*capture.sensorXyz - *t.view.position)) +
                        double(glm::length(*capture.laserXyz - glm::vec3(0.0f, 1.0f, 0.3f)));
    EXPECT_EQ(t.view.pathOffset, float(legs));
  }
}

TEST_F(ExperimentCaptureTest, BadCaptureTargetsNameTheFieldAndTheFile) {
  writeCaptureTal(m_dir / "wall.hdf5", wallCapture());
  const std::string file = (m_dir / "experiment.json").string();
  expectError([&] { parse({{"capture", "wall.hdf5"}}); }, {file, "targets[0].lights", "missing"});
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", json::array()}}); }, {"targets[0].lights", "empty list"});
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", {"lamp"}}}); }, {"targets[0].lights[0]", "lamp"});
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", {"laser", "laser"}}}); }, {"targets[0].lights[1]", "twice"});
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", {"laser"}}, {"image", "x.exr"}}); },
              {"targets[0].image", "not with \"capture\""});
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", {"laser"}}, {"gate", {{"spec", "box:1,2"}}}}); },
              {"targets[0].gate", "not with \"capture\""});
  expectError([&] { parse({{"scan", "scan.json"}, {"lights", {"laser"}}, {"image", "x.exr"}}); }, {"targets[0].lights", "only with"});
  expectError([&] { parse({{"capture", "none.hdf5"}, {"lights", {"laser"}}}); },
              {file, "targets[0].capture", (m_dir / "none.hdf5").string(), "file not found"});
  // The capture's own errors, after the field.
  {
    // validateCapture would refuse to write it: write the bad shape with the HDF5 API.
    writeCaptureTal(m_dir / "bad.hdf5", wallCapture());
    const hid_t f = H5Fopen((m_dir / "bad.hdf5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, "H", H5P_DEFAULT);
    const hsize_t dims[3] = {4, 2, 3};
    const hid_t space = H5Screate_simple(3, dims, nullptr);
    const hid_t d = H5Dcreate2(f, "H", H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, wallCapture().H.data());
    H5Dclose(d);
    H5Sclose(space);
    H5Fclose(f);
  }
  expectError([&] { parse({{"capture", "bad.hdf5"}, {"lights", {"laser"}}}); },
              {file, "targets[0].capture", (m_dir / "bad.hdf5").string(), "sensor_grid_xyz", "does not match H's sensor axes (2, 3)"});
  Capture early = wallCapture();
  early.tStart = -0.5;
  writeCaptureTal(m_dir / "early.hdf5", early);
  expectError([&] { parse({{"capture", "early.hdf5"}, {"lights", {"laser"}}}); }, {"targets[0].capture", "t_start", ">= 0"});
  Capture flat = wallCapture();
  flat.sensor.normals[3] = glm::vec3(0.0f);
  writeCaptureTal(m_dir / "flat.hdf5", flat);
  expectError([&] { parse({{"capture", "flat.hdf5"}, {"lights", {"laser"}}}); },
              {"targets[0].capture", "sensor_grid_normals", "zero"});
  // A pinhole scene cannot take one.
  std::ifstream in(kScene);
  json pinhole = json::parse(in);
  pinhole["camera"] = {{"type", "perspective"}, {"position", {0, 3, 0}}, {"look_at", {0, 0, 0}}, {"up", {0, 0, 1}}};
  test::writePlain(m_dir / "pinhole.json", pinhole.dump());
  expectError([&] { parse({{"capture", "wall.hdf5"}, {"lights", {"laser"}}}, "pinhole.json"); },
              {"targets[0].capture", "point sensor"});
}

}  // namespace
}  // namespace vktg
