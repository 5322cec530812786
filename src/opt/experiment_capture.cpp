#include "opt/experiment_capture.h"

#include <cmath>

#include "io/nlos_capture.h"
#include "vktg/error.h"

namespace vktg {
namespace {

constexpr double kMaxPathOffset = 1e6;  // metres, as a view's path_offset allows
constexpr uint32_t kMaxBins = 65536;    // as a bins gate of a scene allows

}  // namespace

CaptureTargets captureTargets(const std::filesystem::path& path, const std::vector<uint32_t>& lights, const JsonValue& field) {
  Capture capture;
  try {
    capture = readCapture(path);
  } catch (const Error& e) {
    field.fail(e.what());
  }
  const std::string file = path.string();
  CaptureTargets out;
  out.gate.type = GateType::Bins;
  out.gate.binStart = capture.tStart;
  out.gate.binWidth = capture.deltaT;
  out.gate.binCount = capture.bins();
  if (capture.tStart < 0)
    field.fail(file + ": t_start: " + formatNumber(capture.tStart) + " m: the bins of a gate start at a path length >= 0");
  if (capture.bins() > kMaxBins)
    field.fail(file + ": H: " + std::to_string(capture.bins()) + " time bins; a bins gate has at most " + std::to_string(kMaxBins));
  try {
    validateGate(out.gate, file, "t_start, delta_t, H");
  } catch (const Error& e) {
    field.fail(e.what());
  }
  const glm::uvec2 size = captureImageSize(capture);
  out.columns = size.x;
  out.rows = size.y;
  out.grid = capture.hFormat == CaptureHFormat::T_Sx_Sy;
  for (const CaptureView& v : captureViews(capture)) {
    SceneView view;
    const glm::vec3 s = capture.sensor.positions[v.sensor], l = capture.laser.positions[v.laser];
    const glm::vec3 normal = capture.sensor.normals[v.sensor];
    if (!(glm::length(normal) > 0))
      field.fail(file + ": sensor_grid_normals: the normal at sensor point " + std::to_string(v.sensor) +
                 " is zero: the point sensor there would face nowhere");
    view.position = s;
    view.normal = glm::normalize(normal);
    for (uint32_t light : lights) view.lightPositions.emplace_back(light, l);
    if (capture.tAccountsFirstAndLastBounces) {
      // The legs device -> wall and wall -> device that the capture's times include (validateCapture
      // makes sure both devices are there).
      const double legs = double(glm::length(*capture.sensorXyz - s)) + double(glm::length(*capture.laserXyz - l));
      if (!(legs <= kMaxPathOffset))
        field.fail(file + ": sensor_xyz, laser_xyz: the legs to wall point " + std::to_string(v.sensor) + " are " +
                   formatNumber(legs) + " m, more than the 1e6 m a view's path offset may be");
      view.pathOffset = float(legs);
    }
    out.views.push_back(std::move(view));
  }
  return out;
}

ImageSet captureTargetImage(const std::filesystem::path& path, const std::string& file, const std::string& field) {
  try {
    return captureImage(readCapture(path));
  } catch (const Error& e) {
    fail(file, field, e.what());
  }
}

}  // namespace vktg
