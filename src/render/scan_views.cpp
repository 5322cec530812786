#include "render/scan_views.h"

#include "scene/seeds.h"

namespace vktg {

std::vector<RenderView> scanViews(const Scan& scan, const Scene& scene) {
  std::vector<RenderView> views;
  for (size_t k = 0; k < scan.views.size(); ++k)
    views.push_back({cameraSeenFrom(scene.camera, scan.views[k]), derivedSeed((uint64_t(scene.render.seed) << 32) ^ k),
                     scan.views[k].lightPositions, scan.views[k].pathOffset});
  return views;
}

ImageSet scanImage(ImageSet stacked, const Scan& scan, CameraType camera) {
  if (camera == CameraType::PointSensor) {
    stacked.width = scan.columns;
    stacked.height = scan.rows;
  }
  return stacked;
}

}  // namespace vktg
