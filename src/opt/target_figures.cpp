#include "opt/target_figures.h"

#include <algorithm>
#include <system_error>

#include "opt/plot.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// Path length at the middle of bin k (a transient's gate is a bins gate).
double binCentre(const Gate& gate, size_t k) { return gate.binStart + (double(k) + 0.5) * gate.binWidth; }

// Bin k of a transient.
float binValue(const ImageSet& image, size_t k) { return image.layers[k].pixels[0]; }

void requireTransient(const fs::path& path, const std::string& role, const ImageSet& image, size_t bins) {
  if (!isTransient(image) || image.layers.size() != bins)
    fail(path.string(), role, "a transient of " + std::to_string(bins) + " bins at one pixel was expected, not " +
                                  std::to_string(image.width) + " x " + std::to_string(image.height) + " pixels with " +
                                  std::to_string(image.layers.size()) + " layers");
}

// The three images of a target, by caption.
std::vector<std::pair<std::string, const ImageSet*>> roles(const TargetImages& t, uint64_t iteration) {
  return {{"target", t.target}, {"initial", t.initial}, {"iteration " + std::to_string(iteration), t.current}};
}

void writeTransientPlot(const fs::path& path, const TargetImages& t, uint64_t iteration) {
  const size_t bins = t.target->layers.size();
  LinePlot plot;
  plot.title = t.name;
  plot.xLabel = "path length (m)";
  plot.yLabel = "value";
  for (const auto& [caption, image] : roles(t, iteration)) {
    requireTransient(path, caption, *image, bins);
    PlotSeries series{caption, {}, {}};
    for (size_t k = 0; k < bins; ++k) {
      series.x.push_back(binCentre(t.gate, k));
      series.y.push_back(binValue(*image, k));
    }
    plot.series.push_back(std::move(series));
  }
  writeLinePlot(path, plot, 640, 400);
}

void writeScan(const fs::path& path, const std::vector<const TargetImages*>& scan, uint64_t iteration) {
  const uint32_t rows = uint32_t(scan.size()), bins = uint32_t(scan.front()->target->layers.size());
  std::vector<std::pair<std::string, std::vector<float>>> panels;
  for (const auto& role : roles(*scan.front(), iteration)) panels.push_back({role.first, {}});
  for (const TargetImages* t : scan) {
    const auto images = roles(*t, iteration);
    for (size_t r = 0; r < images.size(); ++r) {
      requireTransient(path, t->name + " " + images[r].first, *images[r].second, bins);
      for (size_t k = 0; k < bins; ++k) panels[r].second.push_back(binValue(*images[r].second, k));
    }
  }
  const Gate& gate = scan.front()->gate;
  writeTransientScan(path, rows, bins, panels, gate.binStart, gate.binStart + bins * gate.binWidth);
}

}  // namespace

bool isTransient(const ImageSet& image) {
  return image.width == 1 && image.height == 1 && image.layers.size() > 1;
}

void writeTargetFigures(const fs::path& directory, uint64_t iteration, const std::vector<TargetImages>& targets) {
  const std::string suffix = "_" + std::to_string(iteration) + ".png";
  // Transient targets grouped by gate, groups in order of their first target.
  std::vector<std::vector<const TargetImages*>> scans;
  for (const TargetImages& t : targets) {
    if (!isTransient(*t.target)) {
      writeImageStrip(directory / (t.name + suffix), {{"target", *t.target}, {"initial", *t.initial},
                                                      {"iteration " + std::to_string(iteration), *t.current}});
      continue;
    }
    auto same = [&](const std::vector<const TargetImages*>& scan) { return scan.front()->gate == t.gate; };
    auto scan = std::find_if(scans.begin(), scans.end(), same);
    if (scan == scans.end()) scans.push_back({&t});
    else scan->push_back(&t);
  }
  size_t shared = 0;  // scans of two or more points written so far
  for (const std::vector<const TargetImages*>& scan : scans) {
    if (scan.size() <= kMaxTransientPlots)
      for (const TargetImages* t : scan) writeTransientPlot(directory / (t->name + suffix), *t, iteration);
    if (scan.size() < 2) continue;
    std::error_code error;
    fs::create_directories(directory / "transients", error);
    if (error) fail((directory / "transients").string(), "", "cannot create the directory: " + error.message());
    const std::string name = std::to_string(iteration) + (shared > 0 ? "_" + std::to_string(shared) : "") + ".png";
    writeScan(directory / "transients" / name, scan, iteration);
    ++shared;
  }
}

}  // namespace vktg
