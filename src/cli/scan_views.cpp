#include "cli/scan_views.h"

#include "scene/seeds.h"

namespace vktg::cli {

OptionSpec scanOption(const char* what) {
  return {"--scan", "FILE.json",
          std::string(what) + " of every view of a scan file (a grid of sensor and laser positions on a relay wall, or a "
                              "list of views), the views rendered together; at a point sensor the image is the scan grid, one pixel per "
                              "point (docs/scene-format.md, Scans); behind a pinhole the views' images one below the other"};
}

std::optional<Scan> scanOf(const ParsedArgs& args, const Scene& scene, std::vector<std::filesystem::path>& inputs) {
  auto file = args.get("--scan");
  if (!file) return std::nullopt;
  inputs.push_back(*file);
  return loadScan(*file, scene);
}

std::vector<RenderView> scanViews(const Scan& scan, const Scene& scene) {
  std::vector<RenderView> views;
  for (size_t k = 0; k < scan.views.size(); ++k)
    views.push_back({cameraSeenFrom(scene.camera, scan.views[k]), derivedSeed((uint64_t(scene.render.seed) << 32) ^ k),
                     scan.views[k].lightPositions});
  return views;
}

ImageSet scanImage(ImageSet stacked, const Scan& scan, CameraType camera) {
  if (camera == CameraType::PointSensor) {
    stacked.width = scan.columns;
    stacked.height = scan.rows;
  }
  return stacked;
}

}  // namespace vktg::cli
