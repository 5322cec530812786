#include "cli/scan_views.h"

namespace vktg::cli {

OptionSpec scanOption(const char* what) {
  return {"--scan", "FILE.json",
          std::string(what) + " of every view of a scan file (a grid of sensor and laser positions on a relay wall, or a "
                              "list of views), the views rendered together (default: a Mitsuba nlos_capture_meter's own grid); at a point sensor the image is the scan grid, one pixel per "
                              "point (docs/scene-format.md, Scans); behind a pinhole the views' images one below the other"};
}

std::optional<Scan> scanOf(const ParsedArgs& args, const Scene& scene, std::vector<std::filesystem::path>& inputs,
                           std::optional<Scan> capture) {
  auto file = args.get("--scan");
  if (!file) return capture;
  inputs.push_back(*file);
  return loadScan(*file, scene);
}

}  // namespace vktg::cli
