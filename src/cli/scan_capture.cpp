#include "cli/scan_capture.h"

#include "vktg/error.h"

namespace vktg::cli {
namespace {

[[noreturn]] void failOut(const std::filesystem::path& out, const std::string& problem) {
  fail("--out", out.string(), problem);
}

// Where the scene's point lights are in view k (moved as the view says).
std::vector<glm::vec3> lightsIn(const Scene& scene, const SceneView& view) {
  std::vector<glm::vec3> positions;
  for (const PointLight& light : scene.pointLights) positions.push_back(light.position);
  for (const auto& [light, position] : view.lightPositions) positions.at(light) = position;
  return positions;
}

}  // namespace

bool isCapturePath(const std::filesystem::path& out) { return out.extension() == ".hdf5" || out.extension() == ".h5"; }

void checkScanCapture(const Scene& scene, const std::optional<Scan>& scan, const std::filesystem::path& out) {
  if (!scan) failOut(out, "an NLOS capture holds the transients of a scan: give --scan");
  if (scene.camera.type != CameraType::PointSensor)
    failOut(out, "an NLOS capture is measured by a point sensor at each wall point; the scene's camera is a pinhole");
  if (scene.gate.type != GateType::Bins)
    failOut(out, "an NLOS capture holds transients in time bins; the scene's gate is " + scene.gate.describe() +
                     " (give a bins gate, e.g. --gate bins:START,WIDTH,COUNT)");
  if (scene.pointLights.empty())
    failOut(out, "an NLOS capture needs its laser: the scene has no point light");
  for (size_t k = 0; k < scan->views.size(); ++k) {
    const SceneView& view = scan->views[k];
    if (view.pathOffset != 0.0f)
      failOut(out, "view " + std::to_string(k) + " counts " + std::to_string(view.pathOffset) +
                       " m of path outside the scene; the captures vktg writes count no device legs");
    const std::vector<glm::vec3> lights = lightsIn(scene, view);
    for (size_t l = 1; l < lights.size(); ++l)
      if (lights[l] != lights[0])
        failOut(out, "in view " + std::to_string(k) + " the point lights \"" + scene.pointLights[0].name + "\" and \"" +
                         scene.pointLights[l].name + "\" are at different places; a capture has one laser point per measurement");
  }
}

Capture scanCapture(const Scene& scene, const Scan& scan, const ImageSet& image, const std::string& info) {
  Capture c;
  c.hFormat = scan.grid ? CaptureHFormat::T_Sx_Sy : CaptureHFormat::T_Si;
  const size_t views = scan.views.size();
  c.sensor.shape = scan.grid ? std::vector<uint32_t>{scan.columns, scan.rows} : std::vector<uint32_t>{uint32_t(views)};
  c.sensor.positions.resize(views);
  c.sensor.normals.resize(views);
  std::vector<glm::vec3> lasers(views);
  for (size_t k = 0; k < views; ++k) {
    // Grid point (i, j) (view j * columns + i) at i * rows + j in the capture's (X, Y) order.
    const size_t at = scan.grid ? (k % scan.columns) * scan.rows + k / scan.columns : k;
    const SceneView& view = scan.views[k];
    c.sensor.positions[at] = view.position.value_or(scene.camera.position);
    c.sensor.normals[at] = view.normal.value_or(scene.camera.normal);
    lasers[at] = lightsIn(scene, view).front();
  }
  bool fixed = true;
  for (const glm::vec3& p : lasers) fixed = fixed && p == lasers.front();
  if (fixed) {
    // One laser point for every view; a point light has no surface, so its normal is the sensor's.
    c.laser.shape = scan.grid ? std::vector<uint32_t>{1, 1} : std::vector<uint32_t>{1};
    c.laser.positions = {lasers.front()};
    c.laser.normals = {scene.camera.normal};
  } else {
    c.laser.shape = c.sensor.shape;
    c.laser.positions = lasers;
    c.laser.normals = c.sensor.normals;  // the laser's point is the sensor's (confocal), or beside it on the wall
  }
  c.dims = {uint32_t(image.layers.size())};
  c.dims.insert(c.dims.end(), c.sensor.shape.begin(), c.sensor.shape.end());
  c.H = captureH(image, c.hFormat);
  c.deltaT = scene.gate.binWidth;
  c.tStart = scene.gate.binStart;
  // Paths start at the laser's wall point and end at the sensor's: no device legs. tal's readers
  // still reshape the device positions, so they hold the scene's own sensor and first light.
  c.tAccountsFirstAndLastBounces = false;
  c.sensorXyz = scene.camera.position;
  c.laserXyz = scene.pointLights.front().position;
  c.confocal = gridsCoincide(c.laser, c.sensor);
  c.sceneInfo = info;
  return c;
}

}  // namespace vktg::cli
