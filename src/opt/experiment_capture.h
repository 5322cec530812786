// Experiment targets from NLOS capture files (docs/optimize.md, "Captures"): a capture is a scan
// whose views are its sensor points (with the listed point lights at its laser points), whose gate
// is its bins and whose image is its H, laid out as `vktg render --scan` writes a scan's.
#pragma once
#include <filesystem>
#include <vector>

#include "scene/scene_values.h"
#include "scene/scene_view.h"
#include "vktg/gate.h"
#include "vktg/image_io.h"

namespace vktg {

struct CaptureTargets {
  std::vector<SceneView> views;  // in the order of the capture's image (captureViews)
  Gate gate;                     // bins [t_start + k delta_t, t_start + (k + 1) delta_t)
  uint32_t columns = 0, rows = 0;
  bool grid = false;             // a T_Sx_Sy grid, its targets named by column and row
};

// Reads the capture at `path` for a target whose `lights` (Scene::pointLights indices) sit at its
// laser points. Where the capture's times count the legs to and from its devices, each view counts
// them as path outside the scene: |sensor_xyz - s| + |laser_xyz - l| for sensor point s and laser
// point l. Errors name `field` (the target's "capture") and then the file's own message.
CaptureTargets captureTargets(const std::filesystem::path& path, const std::vector<uint32_t>& lights, const JsonValue& field);

// The capture's H as the target image of its scan (captureImage). Errors name `file` and `field`.
ImageSet captureTargetImage(const std::filesystem::path& path, const std::string& file, const std::string& field);

}  // namespace vktg
