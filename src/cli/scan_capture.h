// `vktg render --scan SCAN --out FILE.hdf5`: a rendered point-sensor scan as an NLOS capture in
// tal's layout (docs/scene-format.md, "NLOS captures (HDF5)"). Whether the scene and scan can be
// one is checked before anything renders; every error names --out.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "io/nlos_capture.h"
#include "scene/scan.h"
#include "vktg/scene.h"

namespace vktg::cli {

// Whether `out` names a capture file (.hdf5 or .h5).
bool isCapturePath(const std::filesystem::path& out);

// Throws vktg::Error "--out: FILE: problem" unless the scan's transients make a tal capture: a scan
// at a point sensor behind a bins gate, one laser (the scene's point lights at one place) in every
// view, and no view counting path outside the scene.
void checkScanCapture(const Scene& scene, const std::optional<Scan>& scan, const std::filesystem::path& out);

// The capture of `scan` rendered into `image` (laid out by scanImage): a grid as T_Sx_Sy, a list as
// T_Si; the laser grid the lasers' positions (one point when they never move); times without the
// device legs. `info` becomes scene_info.
Capture scanCapture(const Scene& scene, const Scan& scan, const ImageSet& image, const std::string& info);

}  // namespace vktg::cli
