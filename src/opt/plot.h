// PNG figures of a `vktg optimize` run, drawn without external tools: line plots (loss, parameter
// error), image strips (target / initial / current) and heightfield comparisons.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "vktg/image_io.h"

namespace vktg {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};

struct LinePlot {
  std::string title, xLabel, yLabel;
  bool logY = false;                // non-positive values are skipped on a log axis
  std::vector<PlotSeries> series;
};

// Axes with ticks and numbers, one colour per series, a legend; written atomically.
void writeLinePlot(const std::filesystem::path& path, const LinePlot& plot, uint32_t width = 800, uint32_t height = 500);

// Tiles side by side with captions, each tone-mapped with one shared exposure (first layer of each image).
void writeImageStrip(const std::filesystem::path& path, const std::vector<std::pair<std::string, ImageSet>>& tiles);

// Two height maps (nx x nz, row-major) side by side with their difference, one shared colour scale.
void writeHeightfieldComparison(const std::filesystem::path& path, uint32_t nx, uint32_t nz,
                                const std::vector<double>& recovered, const std::vector<double>& truth);

}  // namespace vktg
