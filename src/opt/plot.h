// PNG figures of a `vktg optimize` run, drawn without external tools: line plots (loss, parameter
// error), image strips (target / initial / current), the transients of a scan and heightfield
// comparisons.
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

// Axes with ticks and numbers (ends rounded out to whole ticks; a log axis in whole decades), one
// colour per series, a legend of the named series; written atomically. A point with a coordinate
// that is not finite or beyond +-1e300 (or y <= 0 on a log axis) is not drawn and breaks its line. Throws vktg::Error naming the file for a
// series whose x and y differ in length, a size below 200 x 150, or a failed write.
void writeLinePlot(const std::filesystem::path& path, const LinePlot& plot, uint32_t width = 800, uint32_t height = 500);

// Tiles side by side with captions under them. Each tile shows the sum of its image's layers (a
// transient stack shows its total), tone-mapped with one exposure shared by all tiles so that they
// compare by brightness; tiles are magnified to at least 128 pixels on their longest side or
// box-filtered to at most 512. Throws vktg::Error naming the file for a malformed image.
void writeImageStrip(const std::filesystem::path& path, const std::vector<std::pair<std::string, ImageSet>>& tiles);

// The transients of a scan side by side, one panel per entry (e.g. target, initial, current), each
// `rows` x `bins` values, row-major: a row per scan point (top to bottom), a column per time bin
// (left to right, from path length `firstLength` to `lastLength`, printed under the panels). The
// panels are grey on one exposure so that they compare by brightness; with two or more, one more
// panel shows the last minus the first in a diverging scale (blue below, red above, its largest
// magnitude printed). Bins are magnified to at least 128 pixels across, rows to at least 128 down;
// more than 512 of either are averaged in blocks. Throws vktg::Error naming the file for no panels
// or a panel of the wrong size.
void writeTransientScan(const std::filesystem::path& path, uint32_t rows, uint32_t bins,
                        const std::vector<std::pair<std::string, std::vector<float>>>& panels, double firstLength,
                        double lastLength);

// Two height maps (nx x nz, row-major: value j * nx + i at column i, row j, as a heightfield's
// heights) side by side in one sequential colour scale (viridis), then their difference
// (recovered - truth) in a diverging scale symmetric about 0, each with a labelled colour bar.
// Panels are at most 240 pixels on their longest side (large grids are box-filtered). Throws
// vktg::Error naming the file for maps of the wrong size or with non-finite values.
void writeHeightfieldComparison(const std::filesystem::path& path, uint32_t nx, uint32_t nz,
                                const std::vector<double>& recovered, const std::vector<double>& truth);

}  // namespace vktg
