// A scan's views as the renderer takes them, and the image of a scan from the render of all its
// views (`vktg render --scan`, `vktg grad --scan` and the library's scans share these).
#pragma once
#include <vector>

#include "render/renderer.h"
#include "scene/scan.h"

namespace vktg {

// The render views of a scan: each view's camera and lights, and its own random numbers (the same
// derived seed whichever command renders it, so a view's image is the one-view render's).
std::vector<RenderView> scanViews(const Scan& scan, const Scene& scene);

// A scan's image from the render of its views: at a point sensor (one pixel per view) the grid,
// view j * columns + i at pixel (i, j); behind a pinhole the views' images one below the other, as
// the render stacks them.
ImageSet scanImage(ImageSet stacked, const Scan& scan, CameraType camera);

}  // namespace vktg
