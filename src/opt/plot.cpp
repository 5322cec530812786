// The PNG figures of a run (plot.h), drawn on a Canvas: line plots with axes, ticks, labels and a
// legend; image strips; heightfield comparisons with colour scale bars.
#include "opt/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "io/io_internal.h"
#include "opt/canvas.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kBlack{0, 0, 0};
constexpr Rgb kGrid{225, 225, 225};
constexpr Rgb kSeriesColours[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                                  {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
constexpr int kMargin = 12;
constexpr int kTickLength = 5;
constexpr int kSeriesThickness = 3;
constexpr int kLegendSwatch = 24;
constexpr int kTextScale = 2;
constexpr uint32_t kMinPlotWidth = 200, kMinPlotHeight = 150;
constexpr int kPixelsPerXTick = 120, kPixelsPerYTick = 70;
constexpr int kMaxDecadeTicks = 8;
constexpr double kMaxLinearTicks = 1000;
// Larger magnitudes (and NaN) are not drawn: spans of such values would overflow.
constexpr double kMaxPlotValue = 1e300;
// Image strips: tiles are magnified to at least kStripMinTile pixels on their longest side and
// box-filtered down to at most kStripMaxTile.
constexpr uint32_t kStripMinTile = 128, kStripMaxTile = 512;
constexpr uint32_t kPanelSize = 240;  // heightfield panels, pixels on the longest side
constexpr int kGap = 10;
constexpr int kBarHeight = 14;
// Viridis, sampled at 0, 1/8, ..., 1 (matplotlib's values), interpolated linearly.
constexpr Rgb kViridis[] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
                            {39, 173, 129}, {92, 200, 99}, {170, 220, 50}, {253, 231, 37}};

// One axis: its ends in drawing units (log10 of the value on a log axis), its ticks as values.
struct Axis {
  double low = 0, high = 1;
  std::vector<double> ticks;
  std::vector<std::string> labels;
  bool log = false;
  double map(double value) const { return log ? std::log10(value) : value; }
  double fraction(double value) const { return (map(value) - low) / (high - low); }
};

// 1, 2 or 5 times a power of ten, near span / count.
double niceStep(double span, int count) {
  const double raw = span / std::max(count, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (raw <= m * magnitude * (1 + 1e-9)) return m * magnitude;
  return 10 * magnitude;
}

std::string formatTick(double value, double step) {
  if (std::abs(value) < step * 1e-6) value = 0;  // no "-0" or 1e-17 left by rounding
  char text[32];
  if (step >= 1e-4 && std::abs(value) < 1e6)
    std::snprintf(text, sizeof text, "%.*f", std::max(0, int(-std::floor(std::log10(step) + 1e-9))), value);
  else
    std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

std::string formatDecade(int exponent) {
  if (exponent >= 0 && exponent <= 4) return std::to_string(int(std::lround(std::pow(10.0, exponent))));
  if (exponent < 0 && exponent >= -3) return "0." + std::string(size_t(-exponent - 1), '0') + "1";
  return "1e" + std::to_string(exponent);
}

std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value == 0 ? 0.0 : value);
  return text;
}

// Ends rounded out to whole steps, so ticks sit on both ends.
Axis linearAxis(double low, double high, int tickCount) {
  if (!(low <= high)) {  // nothing to show
    low = 0;
    high = 1;
  }
  if (low == high) {
    const double pad = low == 0 ? 1.0 : 0.1 * std::abs(low);
    low -= pad;
    high += pad;
  }
  Axis axis;
  const double step = niceStep(high - low, tickCount);
  const double first = std::floor(low / step + 1e-9), last = std::ceil(high / step - 1e-9);
  if (!(last - first >= 1 && last - first <= kMaxLinearTicks) || first + 1 == first) {
    // A span too narrow for double precision at this magnitude: the data's own ends, unrounded.
    axis.low = low;
    axis.high = high;
    axis.ticks = {low, high};
    axis.labels = {shortNumber(low), shortNumber(high)};
    return axis;
  }
  axis.low = first * step;
  axis.high = last * step;
  for (double k = first; k <= last; ++k) {
    axis.ticks.push_back(k * step);
    axis.labels.push_back(formatTick(k * step, step));
  }
  return axis;
}

// Whole decades; low and high are positive.
Axis logAxis(double low, double high) {
  if (!(low <= high)) {  // nothing to show
    low = 1;
    high = 10;
  }
  const int first = int(std::floor(std::log10(low) + 1e-9));
  int last = int(std::ceil(std::log10(high) - 1e-9));
  if (last <= first) last = first + 1;
  const int every = std::max(1, (last - first + kMaxDecadeTicks - 1) / kMaxDecadeTicks);
  Axis axis;
  axis.log = true;
  axis.low = first;
  axis.high = last;
  for (int e = first; e <= last; e += every) {
    axis.ticks.push_back(std::pow(10.0, e));
    axis.labels.push_back(formatDecade(e));
  }
  return axis;
}

bool drawable(const LinePlot& plot, double x, double y) {
  return std::abs(x) <= kMaxPlotValue && std::abs(y) <= kMaxPlotValue && (!plot.logY || y > 0);
}

Rgb viridis(double t) {
  const double position = std::clamp(t, 0.0, 1.0) * double(std::size(kViridis) - 1);
  const size_t i = std::min(size_t(position), std::size(kViridis) - 2);
  const double f = position - double(i);
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = uint8_t(std::lround(kViridis[i][c] * (1 - f) + kViridis[i + 1][c] * f));
  return out;
}

Rgb grey(uint8_t level) { return {level, level, level}; }

void centredText(Canvas& canvas, int centre, int y, const std::string& text) {
  canvas.text(centre - Canvas::textWidth(text, kTextScale) / 2, y, text, kBlack, kTextScale);
}

// A horizontal colour bar [left, left + width) with three labels under it.
void colourBar(Canvas& canvas, int left, int top, int width, const std::function<Rgb(double)>& colour,
               const std::string labels[3]) {
  for (int x = 0; x < width; ++x)
    canvas.fillRect(left + x, top, left + x + 1, top + kBarHeight, colour(width > 1 ? double(x) / (width - 1) : 0.5));
  const int textTop = top + kBarHeight + 3;
  canvas.text(left, textTop, labels[0], kBlack, kTextScale);
  centredText(canvas, left + width / 2, textTop, labels[1]);
  canvas.text(left + width - Canvas::textWidth(labels[2], kTextScale), textTop, labels[2], kBlack, kTextScale);
}

}  // namespace

void writeLinePlot(const fs::path& path, const LinePlot& plot, uint32_t width, uint32_t height) {
  if (width < kMinPlotWidth || height < kMinPlotHeight)
    fail(path.string(), "", "plot size " + std::to_string(width) + "x" + std::to_string(height) + " is below the minimum " +
                                std::to_string(kMinPlotWidth) + "x" + std::to_string(kMinPlotHeight));
  double xLow = INFINITY, xHigh = -INFINITY, yLow = INFINITY, yHigh = -INFINITY;
  for (const PlotSeries& series : plot.series) {
    if (series.x.size() != series.y.size())
      fail(path.string(), "series \"" + series.name + "\"",
           std::to_string(series.x.size()) + " x values for " + std::to_string(series.y.size()) + " y values");
    for (size_t i = 0; i < series.x.size(); ++i) {
      if (!drawable(plot, series.x[i], series.y[i])) continue;
      xLow = std::min(xLow, series.x[i]);
      xHigh = std::max(xHigh, series.x[i]);
      yLow = std::min(yLow, series.y[i]);
      yHigh = std::max(yHigh, series.y[i]);
    }
  }
  const Axis xAxis = linearAxis(xLow, xHigh, int(width) / kPixelsPerXTick);
  const Axis yAxis = plot.logY ? logAxis(yLow, yHigh) : linearAxis(yLow, yHigh, int(height) / kPixelsPerYTick);

  // Layout, from the outside in: title, legend, axis label and tick labels around the frame.
  const int lineHeight = Canvas::textHeight(kTextScale);
  int labelWidth = 0;
  for (const std::string& label : yAxis.labels) labelWidth = std::max(labelWidth, Canvas::textWidth(label, kTextScale));
  const int left = kMargin + (plot.yLabel.empty() ? 0 : lineHeight + 6) + labelWidth + kTickLength + 4;
  const int right = int(width) - kMargin - Canvas::textWidth(xAxis.labels.back(), kTextScale) / 2;
  int top = kMargin + (plot.title.empty() ? 0 : lineHeight + 6);
  struct LegendEntry {
    int x, y;
    size_t series;
  };
  std::vector<LegendEntry> legend;
  int legendX = left;
  for (size_t s = 0; s < plot.series.size(); ++s) {
    if (plot.series[s].name.empty()) continue;
    const int entryWidth = kLegendSwatch + 6 + Canvas::textWidth(plot.series[s].name, kTextScale);
    if (legendX > left && legendX + entryWidth > right) {
      legendX = left;
      top += lineHeight + 2;
    }
    legend.push_back({legendX, top, s});
    legendX += entryWidth + 18;
  }
  if (!legend.empty()) top += lineHeight + 8;
  const int bottom = int(height) - kMargin - (plot.xLabel.empty() ? 0 : lineHeight + 4) - lineHeight - kTickLength - 4;
  if (right - left < 40 || bottom - top < 40)
    fail(path.string(), "", "plot size " + std::to_string(width) + "x" + std::to_string(height) +
                                " leaves no room for the axes and their labels");

  auto pixelX = [&](double x) { return int(std::lround(left + xAxis.fraction(x) * (right - left))); };
  auto pixelY = [&](double y) { return int(std::lround(bottom - yAxis.fraction(y) * (bottom - top))); };

  Canvas canvas(width, height, kWhite);
  for (double t : xAxis.ticks) canvas.fillRect(pixelX(t), top, pixelX(t) + 1, bottom, kGrid);
  for (double t : yAxis.ticks) canvas.fillRect(left, pixelY(t), right, pixelY(t) + 1, kGrid);
  for (size_t s = 0; s < plot.series.size(); ++s) {
    const PlotSeries& series = plot.series[s];
    const Rgb colour = kSeriesColours[s % std::size(kSeriesColours)];
    // A point that cannot be drawn (NaN, or <= 0 on a log axis) breaks the line; a lone point is a dot.
    for (size_t i = 0; i < series.x.size(); ++i) {
      if (!drawable(plot, series.x[i], series.y[i])) continue;
      const bool next = i + 1 < series.x.size() && drawable(plot, series.x[i + 1], series.y[i + 1]);
      const bool previous = i > 0 && drawable(plot, series.x[i - 1], series.y[i - 1]);
      if (next)
        canvas.line(pixelX(series.x[i]), pixelY(series.y[i]), pixelX(series.x[i + 1]), pixelY(series.y[i + 1]), colour,
                    kSeriesThickness);
      else if (!previous)
        canvas.line(pixelX(series.x[i]), pixelY(series.y[i]), pixelX(series.x[i]), pixelY(series.y[i]), colour,
                    kSeriesThickness);
    }
  }
  canvas.fillRect(left, top, right + 1, top + 1, kBlack);
  canvas.fillRect(left, bottom, right + 1, bottom + 1, kBlack);
  canvas.fillRect(left, top, left + 1, bottom + 1, kBlack);
  canvas.fillRect(right, top, right + 1, bottom + 1, kBlack);
  for (size_t i = 0; i < xAxis.ticks.size(); ++i) {
    const int x = pixelX(xAxis.ticks[i]);
    canvas.fillRect(x, bottom + 1, x + 1, bottom + 1 + kTickLength, kBlack);
    centredText(canvas, x, bottom + kTickLength + 4, xAxis.labels[i]);
  }
  for (size_t i = 0; i < yAxis.ticks.size(); ++i) {
    const int y = pixelY(yAxis.ticks[i]);
    canvas.fillRect(left - kTickLength, y, left, y + 1, kBlack);
    const int textX = left - kTickLength - 4 - Canvas::textWidth(yAxis.labels[i], kTextScale);
    canvas.text(textX, y - lineHeight / 3, yAxis.labels[i], kBlack, kTextScale);
  }
  if (!plot.title.empty()) centredText(canvas, (left + right) / 2, kMargin, plot.title);
  if (!plot.xLabel.empty()) centredText(canvas, (left + right) / 2, int(height) - kMargin - lineHeight, plot.xLabel);
  if (!plot.yLabel.empty())
    canvas.text(kMargin, (top + bottom) / 2 - Canvas::textWidth(plot.yLabel, kTextScale) / 2, plot.yLabel, kBlack,
                kTextScale, true);
  for (const LegendEntry& entry : legend) {
    const int middle = entry.y + lineHeight / 3;
    canvas.line(entry.x, middle, entry.x + kLegendSwatch, middle, kSeriesColours[entry.series % std::size(kSeriesColours)],
                kSeriesThickness);
    canvas.text(entry.x + kLegendSwatch + 6, entry.y, plot.series[entry.series].name, kBlack, kTextScale);
  }
  canvas.writePng(path);
}

void writeImageStrip(const fs::path& path, const std::vector<std::pair<std::string, ImageSet>>& tiles) {
  if (tiles.empty()) fail(path.string(), "", "an image strip needs at least one image");
  uint32_t largest = 1;
  for (const auto& [caption, image] : tiles) {
    io::validateImageSet(path, image);
    largest = std::max({largest, image.width, image.height});
  }
  const uint32_t shrink = (largest + kStripMaxTile - 1) / kStripMaxTile;
  const uint32_t magnify = shrink > 1 ? 1 : std::max(1u, kStripMinTile / largest);
  struct Tile {
    uint32_t width, height;
    std::vector<float> pixels;  // the sum of the image's layers, shrunk
  };
  std::vector<Tile> shown;
  for (const auto& [caption, image] : tiles) {
    std::vector<float> sum(size_t(image.width) * image.height, 0.0f);
    for (const ImageLayer& layer : image.layers)
      for (size_t i = 0; i < sum.size(); ++i) sum[i] += layer.pixels[i];
    const uint32_t w = (image.width + shrink - 1) / shrink, h = (image.height + shrink - 1) / shrink;
    shown.push_back({w, h, shrink > 1 ? io::downsample(sum, image.width, image.height, shrink, w, h) : std::move(sum)});
  }
  std::vector<const std::vector<float>*> layers;
  for (const Tile& tile : shown) layers.push_back(&tile.pixels);
  const float exposure = io::radianceExposure(layers);  // one exposure: tiles compare by brightness

  const int lineHeight = Canvas::textHeight(kTextScale);
  int canvasWidth = kGap, tileRows = 0;
  std::vector<int> columns;  // left edge of each tile's column
  for (size_t t = 0; t < tiles.size(); ++t) {
    columns.push_back(canvasWidth);
    canvasWidth += std::max(int(shown[t].width * magnify), Canvas::textWidth(tiles[t].first, kTextScale)) + kGap;
    tileRows = std::max(tileRows, int(shown[t].height * magnify));
  }
  Canvas canvas(uint32_t(canvasWidth), uint32_t(kGap + tileRows + 6 + lineHeight + kGap), kWhite);
  for (size_t t = 0; t < tiles.size(); ++t) {
    const Tile& tile = shown[t];
    const int m = int(magnify);
    for (uint32_t y = 0; y < tile.height; ++y)
      for (uint32_t x = 0; x < tile.width; ++x) {
        const int px = columns[t] + int(x) * m, py = kGap + int(y) * m;
        canvas.fillRect(px, py, px + m, py + m, grey(io::radianceGrey(tile.pixels[size_t(y) * tile.width + x], exposure)));
      }
    centredText(canvas, columns[t] + int(tile.width * magnify) / 2, kGap + tileRows + 6, tiles[t].first);
  }
  canvas.writePng(path);
}

void writeTransientScan(const fs::path& path, uint32_t rows, uint32_t bins,
                        const std::vector<std::pair<std::string, std::vector<float>>>& panels, double firstLength,
                        double lastLength) {
  if (panels.empty() || rows == 0 || bins == 0) fail(path.string(), "", "a scan figure needs panels of at least one value");
  for (const auto& [caption, values] : panels)
    if (values.size() != size_t(rows) * bins)
      fail(path.string(), "panel \"" + caption + "\"",
           std::to_string(values.size()) + " values for " + std::to_string(rows) + " x " + std::to_string(bins));
  // Each axis on its own: bins and scan points are magnified or averaged in blocks independently.
  auto scale = [](uint32_t n, uint32_t& shrink, uint32_t& magnify, uint32_t& shown) {
    shrink = (n + kStripMaxTile - 1) / kStripMaxTile;
    magnify = shrink > 1 ? 1 : std::max(1u, kStripMinTile / n);
    shown = (n + shrink - 1) / shrink;
  };
  uint32_t shrinkX, magnifyX, shownX, shrinkY, magnifyY, shownY;
  scale(bins, shrinkX, magnifyX, shownX);
  scale(rows, shrinkY, magnifyY, shownY);
  std::vector<std::vector<float>> shown;
  for (const auto& panel : panels)
    shown.push_back(io::downsample(panel.second, bins, rows, shrinkX, shrinkY, shownX, shownY));
  std::vector<const std::vector<float>*> layers;
  for (const std::vector<float>& values : shown) layers.push_back(&values);
  const float exposure = io::radianceExposure(layers);  // before the difference joins: brightness only
  std::vector<std::string> captions;
  for (const auto& panel : panels) captions.push_back(panel.first);
  float largestDifference = 0;
  if (panels.size() >= 2) {
    std::vector<float> difference(shown.front().size());
    for (size_t i = 0; i < difference.size(); ++i) {
      difference[i] = shown.back()[i] - shown.front()[i];
      largestDifference = std::max(largestDifference, std::abs(difference[i]));
    }
    shown.push_back(std::move(difference));
    captions.push_back("difference, max " + shortNumber(largestDifference));
  }

  const int lineHeight = Canvas::textHeight(kTextScale);
  const int panelWidth = int(shownX * magnifyX), panelHeight = int(shownY * magnifyY);
  std::vector<int> centres;  // of each panel's column, which fits the panel and its caption
  int canvasWidth = kGap;
  for (const std::string& caption : captions) {
    const int width = std::max(panelWidth, Canvas::textWidth(caption, kTextScale));
    centres.push_back(canvasWidth + width / 2);
    canvasWidth += width + 2 * kGap;  // captions may be as wide as their column
  }
  const int panelTop = kGap + lineHeight + 4, footerTop = panelTop + panelHeight + 6;
  const std::string axis = "path length " + shortNumber(firstLength) + " to " + shortNumber(lastLength) +
                           " m, left to right; " + std::to_string(rows) + " scan points, top to bottom" +
                           (shrinkY > 1 ? " (averaged in blocks of " + std::to_string(shrinkY) + ")" : "");
  canvasWidth = std::max(canvasWidth, 2 * kGap + Canvas::textWidth(axis, kTextScale));
  Canvas canvas(uint32_t(canvasWidth), uint32_t(footerTop + lineHeight + kGap), kWhite);
  for (size_t p = 0; p < shown.size(); ++p) {
    const bool difference = p == panels.size();
    centredText(canvas, centres[p], kGap, captions[p]);
    const int left = centres[p] - panelWidth / 2;
    for (uint32_t y = 0; y < shownY; ++y)
      for (uint32_t x = 0; x < shownX; ++x) {
        const float v = shown[p][size_t(y) * shownX + x];
        const Rgb colour = difference ? io::divergingColor(largestDifference > 0 ? v / largestDifference : 0.0f)
                                      : grey(io::radianceGrey(v, exposure));
        const int px = left + int(x * magnifyX), py = panelTop + int(y * magnifyY);
        canvas.fillRect(px, py, px + int(magnifyX), py + int(magnifyY), colour);
      }
  }
  canvas.text(kGap, footerTop, axis, kBlack, kTextScale);
  canvas.writePng(path);
}

void writeHeightfieldComparison(const fs::path& path, uint32_t nx, uint32_t nz, const std::vector<double>& recovered,
                                const std::vector<double>& truth) {
  const size_t count = size_t(nx) * nz;
  if (count == 0 || recovered.size() != count || truth.size() != count)
    fail(path.string(), "", "height maps of " + std::to_string(recovered.size()) + " and " + std::to_string(truth.size()) +
                                " values for a " + std::to_string(nx) + " x " + std::to_string(nz) + " grid");
  double low = INFINITY, high = -INFINITY, largestDifference = 0;
  std::vector<float> difference(count);
  for (size_t i = 0; i < count; ++i) {
    if (!std::isfinite(recovered[i]) || !std::isfinite(truth[i]))
      fail(path.string(), "", "height " + std::to_string(i) + " is not finite");
    low = std::min({low, recovered[i], truth[i]});
    high = std::max({high, recovered[i], truth[i]});
    difference[i] = float(recovered[i] - truth[i]);
    largestDifference = std::max(largestDifference, std::abs(recovered[i] - truth[i]));
  }
  if (low == high) {
    low -= 0.5;
    high += 0.5;
  }
  if (largestDifference == 0) largestDifference = 1;

  // Panels of at most kPanelSize pixels: large grids are box-filtered, small ones magnified.
  const uint32_t shrink = (std::max(nx, nz) + kPanelSize - 1) / kPanelSize;
  const uint32_t w = (nx + shrink - 1) / shrink, h = (nz + shrink - 1) / shrink;
  const int m = int(std::max(1u, kPanelSize / std::max(w, h)));
  auto panel = [&](const std::vector<float>& values) { return shrink > 1 ? io::downsample(values, nx, nz, shrink, w, h) : values; };
  const std::vector<float> shown[3] = {panel(std::vector<float>(recovered.begin(), recovered.end())),
                                       panel(std::vector<float>(truth.begin(), truth.end())), panel(difference)};

  const int lineHeight = Canvas::textHeight(kTextScale);
  const char* captions[3] = {"recovered", "truth", "recovered - truth"};
  const int panelWidth = int(w) * m, panelHeight = int(h) * m;
  const int column = std::max(panelWidth, Canvas::textWidth(captions[2], kTextScale));
  const int panelTop = kGap + lineHeight + 4, barTop = panelTop + panelHeight + kGap;
  const int footerTop = barTop + kBarHeight + 3 + lineHeight + 6;
  Canvas canvas(uint32_t(4 * kGap + 3 * column), uint32_t(footerTop + lineHeight + kGap), kWhite);
  for (int p = 0; p < 3; ++p) {
    const int left = kGap + p * (column + kGap);
    centredText(canvas, left + panelWidth / 2, kGap, captions[p]);
    for (uint32_t z = 0; z < h; ++z)
      for (uint32_t x = 0; x < w; ++x) {
        const double v = shown[p][size_t(z) * w + x];
        const Rgb colour = p < 2 ? viridis((v - low) / (high - low)) : io::divergingColor(float(v / largestDifference));
        canvas.fillRect(left + int(x) * m, panelTop + int(z) * m, left + int(x + 1) * m, panelTop + int(z + 1) * m, colour);
      }
  }
  const std::string heightLabels[3] = {shortNumber(low), shortNumber(0.5 * (low + high)), shortNumber(high)};
  colourBar(canvas, kGap, barTop, column + kGap + panelWidth, viridis, heightLabels);
  const std::string differenceLabels[3] = {shortNumber(-largestDifference), "0", shortNumber(largestDifference)};
  colourBar(canvas, kGap + 2 * (column + kGap), barTop, panelWidth,
            [](double t) { return io::divergingColor(float(2 * t - 1)); }, differenceLabels);
  canvas.text(kGap, footerTop, "x to the right, z down", kBlack, kTextScale);
  canvas.writePng(path);
}

}  // namespace vktg
