// Scan files (src/scene/scan.h): a grid's points in row order with the lights that follow them, a
// list of views, and the errors of bad files (each naming the file and the field).
#include <gtest/gtest.h>

#include "scene/scan.h"
#include "support/file_test.h"

namespace vktg {
namespace {

using test::expectError;

Scene sensorScene() {
  Scene scene;
  scene.camera.type = CameraType::PointSensor;
  scene.camera.position = glm::vec3(0, 1, 0);
  scene.camera.normal = glm::vec3(0, -1, 0);
  scene.pointLights.push_back({"laser", glm::vec3(0, 1, 0), 1.0f});
  scene.pointLights.push_back({"flash", glm::vec3(2, 2, 2), 1.0f});
  return scene;
}

TEST(Scan, GridPointsGoRowByRowAndTheListedLightsFollowThem) {
  const Scan scan = parseScanJson(R"({"version": 1, "grid": {"corner": [-1, 1, -1], "across": [2, 0, 0],
      "down": [0, 0, 1], "resolution": [3, 2], "normal": [0, -2, 0], "lights": ["laser"]}})",
                                  "scan.json", sensorScene());
  ASSERT_EQ(scan.columns, 3u);
  ASSERT_EQ(scan.rows, 2u);
  ASSERT_EQ(scan.views.size(), 6u);
  for (uint32_t j = 0; j < 2; ++j)
    for (uint32_t i = 0; i < 3; ++i) {
      const SceneView& v = scan.views[j * 3 + i];
      const glm::vec3 expected(-1.0f + float(i), 1.0f, -1.0f + float(j));
      ASSERT_TRUE(v.position.has_value());
      EXPECT_EQ(*v.position, expected) << i << ", " << j;
      EXPECT_EQ(*v.normal, glm::vec3(0, -1, 0)) << "normalised";
      ASSERT_EQ(v.lightPositions.size(), 1u) << "only the laser moves";
      EXPECT_EQ(v.lightPositions[0].first, 0u);
      EXPECT_EQ(v.lightPositions[0].second, expected);
    }
}

TEST(Scan, OnePointPerAxisNeedsNoStepAndAListIsOneRow) {
  const Scene scene = sensorScene();
  const Scan point = parseScanJson(R"({"version": 1, "grid": {"corner": [0, 1, 0], "resolution": [1, 1]}})", "s.json", scene);
  ASSERT_EQ(point.views.size(), 1u);
  EXPECT_EQ(*point.views[0].position, glm::vec3(0, 1, 0));
  EXPECT_TRUE(point.views[0].lightPositions.empty());
  const Scan list = parseScanJson(R"({"version": 1, "views": [{"position": [0, 1, 0]},
      {"position": [1, 1, 0], "lights": {"flash": [1, 2, 3]}}]})", "s.json", scene);
  EXPECT_EQ(list.columns, 2u);
  EXPECT_EQ(list.rows, 1u);
  ASSERT_EQ(list.views[1].lightPositions.size(), 1u);
  EXPECT_EQ(list.views[1].lightPositions[0].first, 1u);
  EXPECT_EQ(list.views[0].pathOffset, 0.0f);
  const Scan legs = parseScanJson(R"({"version": 1, "views": [{"position": [0, 1, 0], "path_offset": 2.5}]})", "s.json", scene);
  EXPECT_EQ(legs.views[0].pathOffset, 2.5f);
}

TEST(Scan, BadFilesNameTheFieldAndTheProblem) {
  const Scene sensor = sensorScene();
  Scene pinhole = sensorScene();
  pinhole.camera.type = CameraType::Perspective;
  pinhole.camera.lookAt = glm::vec3(0, 0, 0);
  pinhole.camera.up = glm::vec3(0, 0, 1);
  const std::string grid = R"("corner": [0, 1, 0], "across": [1, 0, 0], "down": [0, 0, 1], "resolution": [2, 2])";
  struct Case {
    const char* what;
    std::string text;
    const Scene* scene;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"no version", R"({"views": [{}]})", &sensor, {"s.json", "version", "missing"}},
      {"future version", R"({"version": 2, "views": [{}]})", &sensor, {"version", "unsupported version 2"}},
      {"neither", R"({"version": 1})", &sensor, {"s.json", "either a \"grid\" or a list of \"views\""}},
      {"both", R"({"version": 1, "views": [{}], "grid": {)" + grid + "}}", &sensor, {"one of the two"}},
      {"unknown field", R"({"version": 1, "grid": {)" + grid + R"(, "spacing": 1}})", &sensor, {"grid", "spacing"}},
      {"no views", R"({"version": 1, "views": []})", &sensor, {"views", "at least one view"}},
      {"zero step", R"({"version": 1, "grid": {"corner": [0, 1, 0], "resolution": [4, 1]}})", &sensor,
       {"across", "non-zero", "4 points"}},
      {"zero columns", R"({"version": 1, "grid": {"corner": [0, 1, 0], "resolution": [0, 1]}})", &sensor,
       {"grid.resolution[0]"}},
      {"too many", R"({"version": 1, "grid": {)" + grid.substr(0, grid.find("\"resolution\"")) +
                       R"("resolution": [2048, 1024]}})", &sensor, {"resolution", "2097152 points", "at most 1048576"}},
      {"unknown light", R"({"version": 1, "grid": {)" + grid + R"(, "lights": ["lamp"]}})", &sensor,
       {"grid.lights[0]", "unknown point light \"lamp\""}},
      {"normal behind a pinhole", R"({"version": 1, "grid": {)" + grid + R"(, "normal": [0, -1, 0]}})", &pinhole,
       {"grid.normal", "perspective"}},
      {"negative path offset", R"({"version": 1, "views": [{"path_offset": -1}]})", &sensor,
       {"views[0].path_offset", "[0, 1e6] m"}},
      {"look_at at a sensor", R"({"version": 1, "views": [{"look_at": [0, 0, 0]}]})", &sensor,
       {"views[0].look_at", "point sensor"}},
      {"overflowing grid", R"({"version": 1, "grid": {"corner": [3e38, 1, 0], "across": [3e38, 0, 0], "resolution": [2, 1]}})",
       &sensor, {"grid", "grid point (1, 0) is not a finite position"}},
      {"looks at itself", R"({"version": 1, "grid": {"corner": [0, 0, 0], "resolution": [1, 1]}})", &pinhole,
       {"grid", "degenerate view at grid point (0, 0)"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    expectError([&] { parseScanJson(c.text, "s.json", *c.scene); }, c.parts);
  }
}

}  // namespace
}  // namespace vktg
