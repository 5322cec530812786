// What the commands that take --scan share: a scan file's views as render views, and the image of
// a scan from the render that held all of them.
#pragma once
#include <optional>
#include <vector>

#include "cli/args.h"
#include "host/renderer.h"
#include "scene/scan.h"

namespace vktg::cli {

// The --scan option's help, the same for every command that takes it.
OptionSpec scanOption(const char* what);

// The scan named by --scan, if any (its file joins `inputs`, which outputs must not overwrite).
std::optional<Scan> scanOf(const ParsedArgs& args, const Scene& scene, std::vector<std::filesystem::path>& inputs);

// The render views of a scan: each view's camera and lights, and its own random numbers (the same
// derived seed whichever command renders it, so a view's image is the one-view render's).
std::vector<RenderView> scanViews(const Scan& scan, const Scene& scene);

// A scan's image from the render of its views: at a point sensor (one pixel per view) the grid,
// view j * columns + i at pixel (i, j); behind a pinhole the views' images one below the other, as
// the render stacks them.
ImageSet scanImage(ImageSet stacked, const Scan& scan, CameraType camera);

}  // namespace vktg::cli
