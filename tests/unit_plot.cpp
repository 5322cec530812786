// Figures of a run: line plots, image strips, scans of transients and heightfield comparisons,
// decoded back from PNG to check sizes, where a series' pixels land on linear and log axes, shared
// exposures and colours.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "opt/canvas.h"
#include "opt/plot.h"
#include "support/file_test.h"
#include "support/png_decode.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::DecodedPng;
using test::decodePng;
using test::expectError;

const Rgb kFirstSeries{31, 119, 180};
const Rgb kSecondSeries{255, 127, 14};

bool hasColour(const DecodedPng& png, int x, int y, Rgb colour) {
  if (x < 0 || y < 0 || x >= png.width || y >= png.height) return false;
  const uint8_t* p = png.at(x, y);
  return p[0] == colour[0] && p[1] == colour[1] && p[2] == colour[2];
}

// Whether `colour` is within `radius` pixels of (x, y).
bool colourNear(const DecodedPng& png, int x, int y, Rgb colour, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (hasColour(png, x + dx, y + dy, colour)) return true;
  return false;
}

int countColour(const DecodedPng& png, Rgb colour) {
  int count = 0;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x) count += hasColour(png, x, y, colour);
  return count;
}

// The plot frame: the black rectangle whose sides are the longest black runs of the image.
struct Frame {
  int left = 0, right = 0, top = 0, bottom = 0;
};

Frame findFrame(const DecodedPng& png) {
  const Rgb black{0, 0, 0};
  auto longestRun = [&](bool rows, int line) {
    int longest = 0, run = 0;
    for (int i = 0; i < (rows ? png.width : png.height); ++i) {
      run = hasColour(png, rows ? i : line, rows ? line : i, black) ? run + 1 : 0;
      longest = std::max(longest, run);
    }
    return longest;
  };
  int bestRow = 0;
  for (int y = 0; y < png.height; ++y) bestRow = std::max(bestRow, longestRun(true, y));
  int bestColumn = 0;
  for (int x = 0; x < png.width; ++x) bestColumn = std::max(bestColumn, longestRun(false, x));
  Frame frame{png.width, 0, png.height, 0};
  for (int y = 0; y < png.height; ++y)
    if (longestRun(true, y) == bestRow) {
      frame.top = std::min(frame.top, y);
      frame.bottom = std::max(frame.bottom, y);
    }
  for (int x = 0; x < png.width; ++x)
    if (longestRun(false, x) == bestColumn) {
      frame.left = std::min(frame.left, x);
      frame.right = std::max(frame.right, x);
    }
  return frame;
}

class Plots : public test::TempDirTest {};

PlotSeries sampled(const std::string& name, double x0, double x1, int count, double (*f)(double)) {
  PlotSeries series{name, {}, {}};
  for (int i = 0; i < count; ++i) {
    const double x = x0 + (x1 - x0) * i / (count - 1);
    series.x.push_back(x);
    series.y.push_back(f(x));
  }
  return series;
}

TEST_F(Plots, LinearSeriesLandsWhereItsValuesSay) {
  // Data spanning [0, 10] on both axes: the axes end on whole ticks there, so the frame is [0, 10]^2.
  LinePlot plot{"loss", "iteration", "value", false, {sampled("diagonal", 0, 10, 11, [](double x) { return x; })}};
  writeLinePlot(m_dir / "linear.png", plot, 800, 500);
  const DecodedPng png = decodePng(m_dir / "linear.png");
  ASSERT_EQ(png.width, 800);
  ASSERT_EQ(png.height, 500);
  ASSERT_EQ(png.channels, 3);
  const Frame f = findFrame(png);
  EXPECT_GT(f.right - f.left, 500);
  EXPECT_GT(f.bottom - f.top, 250);
  auto at = [&](double x, double y) {
    return std::pair<int, int>{int(std::lround(f.left + x / 10 * (f.right - f.left))),
                               int(std::lround(f.bottom - y / 10 * (f.bottom - f.top)))};
  };
  for (double v : {2.5, 5.0, 7.5}) {
    const auto [x, y] = at(v, v);
    EXPECT_TRUE(colourNear(png, x, y, kFirstSeries, 1)) << "no series pixel at (" << v << ", " << v << ")";
  }
  for (auto [vx, vy] : {std::pair{2.5, 7.5}, std::pair{7.5, 2.5}}) {
    const auto [x, y] = at(vx, vy);
    EXPECT_FALSE(colourNear(png, x, y, kFirstSeries, 3)) << "series pixel at (" << vx << ", " << vy << ")";
  }
  // Title, axis labels and tick labels put dark pixels above, left of and below the frame.
  auto darkIn = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (png.at(x, y)[0] < 64 && png.at(x, y)[1] < 64 && png.at(x, y)[2] < 64) return true;
    return false;
  };
  EXPECT_TRUE(darkIn(0, 0, png.width, 30)) << "no title";
  EXPECT_TRUE(darkIn(0, f.top, f.left - 8, f.bottom)) << "no y tick labels";
  EXPECT_TRUE(darkIn(f.left, f.bottom + 8, f.right, png.height)) << "no x tick labels";
}

TEST_F(Plots, LogAxisIsLinearInTheExponent) {
  // y = 10^x on x in [0, 3]: a straight line from (0, 1) to (3, 1000) on a log axis.
  LinePlot plot{"", "x", "", true, {sampled("power", 0, 3, 31, [](double x) { return std::pow(10.0, x); })}};
  writeLinePlot(m_dir / "log.png", plot, 600, 400);
  const DecodedPng png = decodePng(m_dir / "log.png");
  const Frame f = findFrame(png);
  for (double x : {0.75, 1.5, 2.25}) {
    const int px = int(std::lround(f.left + x / 3 * (f.right - f.left)));
    const int py = int(std::lround(f.bottom - x / 3 * (f.bottom - f.top)));
    EXPECT_TRUE(colourNear(png, px, py, kFirstSeries, 1)) << "x = " << x;
    // On a linear axis 10^1.5 = 31.6 would sit at 3% of the height, not half of it.
    const int linearY = int(std::lround(f.bottom - (std::pow(10.0, x) - 1) / 999 * (f.bottom - f.top)));
    if (std::abs(linearY - py) > 6) EXPECT_FALSE(colourNear(png, px, linearY, kFirstSeries, 2)) << "x = " << x;
  }
}

TEST_F(Plots, NonPositiveValuesAreSkippedOnALogAxisAndNanBreaksTheLine) {
  PlotSeries series{"gappy", {0, 1, 2, 3, 4, 5, 6, 7, 8}, {1, 10, NAN, NAN, NAN, NAN, 0, -1, 100}};
  writeLinePlot(m_dir / "gaps.png", LinePlot{"", "", "", true, {series}}, 800, 500);
  const DecodedPng png = decodePng(m_dir / "gaps.png");
  const Frame f = findFrame(png);
  // The axis spans [0, 8] x [1, 100]: the line from (0, 1) to (1, 10) is drawn, nothing over x in
  // (2, 7), and (8, 100) is a lone dot in the top-right corner.
  auto px = [&](double x) { return int(std::lround(f.left + x / 8 * (f.right - f.left))); };
  auto py = [&](double y) { return int(std::lround(f.bottom - std::log10(y) / 2 * (f.bottom - f.top))); };
  EXPECT_TRUE(colourNear(png, px(0.5), py(std::sqrt(10.0)), kFirstSeries, 1));
  EXPECT_TRUE(colourNear(png, px(8), py(100), kFirstSeries, 1));
  for (int x = px(2.2); x < px(7.8); ++x)
    for (int y = f.top + 2; y < f.bottom - 1; ++y) ASSERT_FALSE(hasColour(png, x, y, kFirstSeries)) << x << ", " << y;
}

TEST_F(Plots, SeriesHaveDistinctColoursAndALegend) {
  LinePlot plot{"two", "i", "v", false,
                {sampled("rising", 0, 1, 5, [](double x) { return x; }), sampled("falling", 0, 1, 5, [](double x) { return 1 - x; })}};
  writeLinePlot(m_dir / "two.png", plot, 800, 500);
  const DecodedPng png = decodePng(m_dir / "two.png");
  const Frame f = findFrame(png);
  EXPECT_TRUE(colourNear(png, (f.left + f.right) / 2, (f.top + f.bottom) / 2, kFirstSeries, 2));
  EXPECT_TRUE(colourNear(png, (f.left + f.right) / 2, (f.top + f.bottom) / 2, kSecondSeries, 2));
  // Legend swatches sit above the frame, one per series.
  auto above = [&](Rgb colour) {
    int count = 0;
    for (int y = 0; y < f.top; ++y)
      for (int x = 0; x < png.width; ++x) count += hasColour(png, x, y, colour);
    return count;
  };
  EXPECT_GT(above(kFirstSeries), 20);
  EXPECT_GT(above(kSecondSeries), 20);
}

TEST_F(Plots, EmptyPlotsAndNonAsciiTextStillDraw) {
  writeLinePlot(m_dir / "empty.png", LinePlot{"θ error — none yet", "", "", true, {}}, 300, 200);
  const DecodedPng png = decodePng(m_dir / "empty.png");
  EXPECT_EQ(png.width, 300);
  EXPECT_EQ(png.height, 200);
}

TEST_F(Plots, ExtremeValuesStillDraw) {
  // Spans near the limits of double: huge, and too narrow for whole ticks at their magnitude.
  const std::vector<PlotSeries> cases[] = {
      {PlotSeries{"huge", {0, 1, 2}, {-1e299, 1e299, 1e301}}},
      {PlotSeries{"narrow", {0, 1}, {1e18, std::nextafter(1e18, 2e18)}}},
      {PlotSeries{"tiny", {1e-310, 2e-310}, {1e-300, 1e-299}}},
  };
  for (const std::vector<PlotSeries>& series : cases) {
    writeLinePlot(m_dir / "extreme.png", LinePlot{"", "", "", false, series}, 400, 300);
    EXPECT_EQ(decodePng(m_dir / "extreme.png").width, 400) << series[0].name;
    writeLinePlot(m_dir / "extreme.png", LinePlot{"", "", "", true, series}, 400, 300);
    EXPECT_EQ(decodePng(m_dir / "extreme.png").height, 300) << series[0].name;
  }
}

TEST_F(Plots, BadPlotsAreErrors) {
  const fs::path path = m_dir / "bad.png";
  expectError([&] { writeLinePlot(path, LinePlot{"", "", "", false, {PlotSeries{"s", {1, 2}, {1}}}}); },
              {path.string(), "series \"s\"", "2 x values for 1 y values"});
  expectError([&] { writeLinePlot(path, LinePlot{}, 100, 100); }, {path.string(), "below the minimum"});
  const fs::path missing = m_dir / "no_such_dir" / "plot.png";
  expectError([&] { writeLinePlot(missing, LinePlot{}); }, {missing.string(), "does not exist"});
  EXPECT_FALSE(fs::exists(path));
}

ImageSet constantImage(uint32_t width, uint32_t height, std::vector<float> layerValues) {
  ImageSet image{width, height, {}};
  for (size_t l = 0; l < layerValues.size(); ++l)
    image.layers.push_back({layerValues.size() > 1 ? "bin" + std::to_string(l) : "",
                            std::vector<float>(size_t(width) * height, layerValues[l])});
  return image;
}

// Runs of non-white pixels along row y: (start, length).
std::vector<std::pair<int, int>> tilesInRow(const DecodedPng& png, int y) {
  std::vector<std::pair<int, int>> runs;
  for (int x = 0; x < png.width; ++x) {
    if (hasColour(png, x, y, {255, 255, 255})) continue;
    if (runs.empty() || runs.back().first + runs.back().second != x) runs.push_back({x, 0});
    ++runs.back().second;
  }
  return runs;
}

TEST_F(Plots, ImageStripSharesOneExposureAndSumsLayers) {
  // A transient stack of two layers of 0.25 shows as its total, 0.5, like the single-layer tile.
  const std::vector<std::pair<std::string, ImageSet>> tiles = {
      {"target", constantImage(16, 8, {1.0f})}, {"initial", constantImage(16, 8, {0.5f})},
      {"stack", constantImage(16, 8, {0.25f, 0.25f})}};
  writeImageStrip(m_dir / "strip.png", tiles);
  const DecodedPng png = decodePng(m_dir / "strip.png");
  // Small tiles are magnified to at least 128 pixels on their longest side.
  const int y = png.height / 4;
  const std::vector<std::pair<int, int>> runs = tilesInRow(png, y);
  ASSERT_EQ(runs.size(), 3u);
  for (const auto& run : runs) EXPECT_EQ(run.second, 128);
  const uint8_t bright = png.at(runs[0].first + 64, y)[0];
  const uint8_t half = png.at(runs[1].first + 64, y)[0];
  EXPECT_GT(bright, half + 30) << "one exposure for all tiles keeps the darker tile darker";
  EXPECT_EQ(png.at(runs[2].first + 64, y)[0], half);
  // Captions under the tiles.
  int dark = 0;
  for (int yy = png.height * 3 / 4; yy < png.height; ++yy)
    for (int x = 0; x < png.width; ++x) dark += png.at(x, yy)[0] < 64;
  EXPECT_GT(dark, 50);
}

TEST_F(Plots, ImageStripRejectsMalformedImages) {
  ImageSet broken = constantImage(4, 4, {1.0f});
  broken.layers[0].pixels.pop_back();
  const fs::path path = m_dir / "strip.png";
  expectError([&] { writeImageStrip(path, {{"broken", broken}}); }, {path.string(), "pixels"});
  expectError([&] { writeImageStrip(path, {}); }, {path.string(), "at least one image"});
  EXPECT_FALSE(fs::exists(path));
}

// The first row from the top whose non-white runs are `count` panels of `width` pixels.
int firstPanelRow(const DecodedPng& png, size_t count, int width) {
  for (int y = 0; y < png.height; ++y) {
    const std::vector<std::pair<int, int>> runs = tilesInRow(png, y);
    if (runs.size() == count && std::all_of(runs.begin(), runs.end(), [&](auto r) { return r.second == width; })) return y;
  }
  return -1;
}

TEST_F(Plots, TransientScanRowsAreScanPointsAndTheDifferenceHasItsSign) {
  // Two scan points of four bins: the current render is above the target on the first, below on
  // the second.
  const std::vector<float> target(8, 0.5f);
  std::vector<float> current = {1, 1, 1, 1, 0.25f, 0.25f, 0.25f, 0.25f};
  writeTransientScan(m_dir / "scan.png", 2, 4, {{"target", target}, {"now", current}}, 1.0, 1.4);
  const DecodedPng png = decodePng(m_dir / "scan.png");
  // Bins and rows are magnified to 128 pixels: 32 per bin, 64 per scan point; the difference is a
  // third panel.
  const int top = firstPanelRow(png, 3, 128);
  ASSERT_GE(top, 0);
  const std::vector<std::pair<int, int>> panels = tilesInRow(png, top);
  const int first = top + 32, second = top + 96;
  EXPECT_EQ(tilesInRow(png, top + 127).size(), 3u);
  EXPECT_EQ(tilesInRow(png, top + 128).size(), 0u) << "two rows of 64 pixels";
  const uint8_t targetGrey = png.at(panels[0].first + 64, first)[0];
  EXPECT_EQ(png.at(panels[0].first + 64, second)[0], targetGrey);
  EXPECT_GT(png.at(panels[1].first + 64, first)[0], targetGrey + 30) << "one exposure for both panels";
  EXPECT_LT(png.at(panels[1].first + 64, second)[0] + 30, targetGrey);
  const uint8_t* above = png.at(panels[2].first + 64, first);
  const uint8_t* below = png.at(panels[2].first + 64, second);
  EXPECT_GT(above[0], above[2] + 50) << "red where the current render is above the target";
  EXPECT_GT(below[2], below[0] + 50) << "blue where it is below";
}

TEST_F(Plots, LongScansAreAveragedInBlocksOfRows) {
  // 1030 scan points of 3 bins: blocks of 3 rows (344 rows shown), bins magnified to 42 pixels.
  writeTransientScan(m_dir / "long.png", 1030, 3, {{"target", std::vector<float>(3090, 1.0f)}}, 0.0, 3.0);
  const DecodedPng png = decodePng(m_dir / "long.png");
  const int top = firstPanelRow(png, 1, 126);
  ASSERT_GE(top, 0);
  int rows = 0;
  while (top + rows < png.height && tilesInRow(png, top + rows).size() == 1 && tilesInRow(png, top + rows)[0].second == 126) ++rows;
  EXPECT_EQ(rows, 344);
}

TEST_F(Plots, TransientScanErrors) {
  const fs::path path = m_dir / "scan.png";
  expectError([&] { writeTransientScan(path, 2, 4, {{"target", std::vector<float>(7)}}, 0, 1); },
              {path.string(), "panel \"target\"", "7 values for 2 x 4"});
  expectError([&] { writeTransientScan(path, 2, 4, {}, 0, 1); }, {path.string(), "panels"});
  EXPECT_FALSE(fs::exists(path));
}

// Rows holding a run of at least `length` pixels of `colour`, and where the first such run starts.
std::vector<std::pair<int, int>> rowsWithRun(const DecodedPng& png, Rgb colour, int length) {
  std::vector<std::pair<int, int>> rows;
  for (int y = 0; y < png.height; ++y) {
    int run = 0;
    for (int x = 0; x < png.width; ++x) {
      run = hasColour(png, x, y, colour) ? run + 1 : 0;
      if (run == length) {
        rows.push_back({y, x - length + 1});
        break;
      }
    }
  }
  return rows;
}

TEST_F(Plots, HeightfieldComparisonShowsTheDifferenceWhereItIs) {
  // 4 x 3 grid, recovered = truth except one cell 1 higher: in a 240-pixel panel each cell is 60
  // pixels, the cell is the only one at the top of the height scale (yellow) in the recovered
  // panel, and the only full red cell (+max difference) in the difference panel, in the same rows.
  const uint32_t nx = 4, nz = 3;
  std::vector<double> truth(nx * nz), recovered(nx * nz);
  for (size_t i = 0; i < truth.size(); ++i) truth[i] = recovered[i] = 0.1 * double(i % 3);
  recovered[2 * nx + 1] += 1.0;
  writeHeightfieldComparison(m_dir / "hf.png", nx, nz, recovered, truth);
  const DecodedPng png = decodePng(m_dir / "hf.png");
  const int cell = 240 / 4;
  const std::vector<std::pair<int, int>> yellow = rowsWithRun(png, {253, 231, 37}, cell / 2);
  const std::vector<std::pair<int, int>> red = rowsWithRun(png, {255, 0, 0}, cell / 2);
  ASSERT_EQ(yellow.size(), size_t(cell));
  ASSERT_EQ(red.size(), size_t(cell));
  for (int r = 0; r < cell; ++r) {
    EXPECT_EQ(yellow[r].first, red[r].first);
    EXPECT_EQ(yellow[r].first, yellow[0].first + r);
  }
  EXPECT_LT(yellow[0].second + 2 * cell, red[0].second);
  // The cell is in the bottom row of three: two cells of other colours above it in the panel.
  EXPECT_GE(yellow[0].first, 2 * cell);
}

TEST_F(Plots, LargeHeightfieldsAreShrunkAndFlatOnesDraw) {
  const uint32_t n = 1000;
  std::vector<double> heights(size_t(n) * n);
  for (size_t i = 0; i < heights.size(); ++i) heights[i] = std::sin(double(i % n) * 0.01);
  writeHeightfieldComparison(m_dir / "large.png", n, n, heights, heights);
  const DecodedPng large = decodePng(m_dir / "large.png");
  EXPECT_LT(large.width, 1000);
  EXPECT_LT(large.height, 400);
  const std::vector<double> flat(9, 2.0);
  writeHeightfieldComparison(m_dir / "flat.png", 3, 3, flat, flat);
  EXPECT_GT(decodePng(m_dir / "flat.png").width, 0);
}

TEST_F(Plots, HeightfieldErrors) {
  const fs::path path = m_dir / "hf.png";
  expectError([&] { writeHeightfieldComparison(path, 2, 2, {0, 0, 0}, {0, 0, 0, 0}); }, {path.string(), "2 x 2 grid"});
  expectError([&] { writeHeightfieldComparison(path, 2, 1, {0, NAN}, {0, 0}); }, {path.string(), "not finite"});
  EXPECT_FALSE(fs::exists(path));
}

TEST(Canvas, TextAndLinesFillTheExpectedPixels) {
  Canvas canvas(64, 32, {255, 255, 255});
  canvas.line(2, 2, 12, 2, {0, 0, 0}, 3);
  for (int x = 2; x <= 12; ++x)
    for (int y = 1; y <= 3; ++y) EXPECT_EQ(canvas.at(x, y), (Rgb{0, 0, 0})) << x << ", " << y;
  EXPECT_EQ(canvas.at(2, 4), (Rgb{255, 255, 255}));
  EXPECT_EQ(canvas.at(14, 2), (Rgb{255, 255, 255}));
  // "I" is one vertical bar: horizontal text fills a tall box, vertical text a wide one.
  const int width = Canvas::textWidth("II", 1);
  Canvas horizontal(32, 32, {255, 255, 255}), vertical(32, 32, {255, 255, 255});
  horizontal.text(0, 0, "II", {0, 0, 0}, 1);
  vertical.text(0, 0, "II", {0, 0, 0}, 1, true);
  int hx = 0, hy = 0, vx = 0, vy = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      if (horizontal.at(x, y)[0] == 0) hx = std::max(hx, x), hy = std::max(hy, y);
      if (vertical.at(x, y)[0] == 0) vx = std::max(vx, x), vy = std::max(vy, y);
    }
  EXPECT_GT(hy, hx / 2) << "horizontal text is taller than a vertical reading";
  EXPECT_LE(hx, width);
  EXPECT_EQ(vx, hy);
  EXPECT_LE(vy, width);
}

}  // namespace
}  // namespace vktg
