// Scan files (docs/scene-format.md, "Scans"): the views of one scene that `vktg render --scan`
// renders together, as a relay-wall capture moves its sensor and laser over a grid. Strict like the
// scene format: every error names the file, the field and the problem.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene_view.h"
#include "vktg/scene.h"

namespace vktg {

// The most views one scan may hold (each is a record of the render's frame block).
inline constexpr uint32_t kMaxScanViews = 1u << 20;

struct Scan {
  std::vector<SceneView> views;  // row by row: view j * columns + i is grid point (i, j)
  uint32_t columns = 0, rows = 0;  // a grid's resolution; a list of views is one row
  bool grid = false;               // a grid (points named by column and row) or a list of views
};

// {"version": 1, "grid": {...}} or {"version": 1, "views": [...]} against `scene` (its camera type
// decides which pose fields apply; lights are the scene's point lights, by name).
Scan parseScanJson(const std::string& text, const std::string& file, const Scene& scene);
Scan loadScan(const std::filesystem::path& path, const Scene& scene);

}  // namespace vktg
