#include "bench/bench_nee.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench/bench_scenes.h"
#include "render/device_scene.h"
#include "render/renderer.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

struct Estimator {
  const char* name;
  NeeMode nee;
  EllipsoidSelection selection;
};

}  // namespace

BenchNeeReport benchNee(VulkanContext& context, const BenchNeeOptions& options) {
  BenchNeeReport report;
  report.device = context.report().name;
  const uint32_t resolution = options.scaledSide(options.resolution);
  const double budget = options.secondsPerPoint * options.scale;
  const Estimator estimators[] = {{"standard", NeeMode::Standard, EllipsoidSelection::Auto},
                                  {"ellipsoidal (descend)", NeeMode::Ellipsoidal, EllipsoidSelection::Descend},
                                  {"ellipsoidal (enumerate)", NeeMode::Ellipsoidal, EllipsoidSelection::Enumerate}};
  Renderer renderer(context);
  for (uint32_t n : options.sizes) {
    const Scene scene = tessellatedRoom(n, resolution);
    const uint64_t triangles = scene.triangleCount();
    options.say("room with a " + std::to_string(n) + "x" + std::to_string(n) + " heightfield: " + std::to_string(triangles) +
        " triangles");
    DeviceScene device(context, scene);
    RenderSetup setup = RenderSetup::of(scene);
    for (const Estimator& e : estimators) {
      if (e.selection == EllipsoidSelection::Enumerate && triangles > options.enumerateMaxTriangles) continue;
      RenderOptions ro;
      ro.nee = e.nee;
      ro.ellipsoidSelection = e.selection;
      ro.memoryBudget = options.memoryBudget;
      // A pilot of one sample per pixel (it also builds the pipelines), then enough samples to
      // fill the time budget.
      setup.settings.spp = 1;
      RenderResult pilot = renderer.render(device, setup, ro);
      const double perPath = pilot.stats.seconds / double(std::max<uint64_t>(pilot.stats.paths, 1));
      const double pixels = double(resolution) * resolution;
      const double wanted = std::max(budget / perPath, double(options.minPaths));
      setup.settings.spp = uint32_t(std::clamp(std::ceil(wanted / pixels), 1.0, double(1u << 20)));
      std::vector<double> costs, rays, empty, means;
      for (uint32_t run = 0; run < options.runs; ++run) {
        setup.settings.seed = run + 1;
        RenderResult r = renderer.render(device, setup, ro);
        costs.push_back(r.stats.seconds / double(r.stats.paths));
        rays.push_back(double(r.stats.extensionRays + r.stats.shadowRays) / r.stats.seconds);
        empty.push_back(r.stats.ellipsoidQueries > 0 ? double(r.stats.ellipsoidEmpty) / r.stats.ellipsoidQueries : 0.0);
        double sum = 0.0;
        for (float v : r.mean.layers[0].pixels) sum += v;
        means.push_back(sum / pixels);
      }
      BenchNeeRow row;
      row.size = n;
      row.triangles = triangles;
      row.estimator = e.name;
      row.secondsPerPath = median(costs);
      row.raysPerSecond = median(rays);
      row.emptyFraction = median(empty);
      row.imageMean = median(means);
      char line[256];
      std::snprintf(line, sizeof line, "  %-24s %u spp: %.3g s per path (%.3g paths/s), %.3g rays/s, image mean %.4g",
                    e.name, setup.settings.spp, row.secondsPerPath, 1.0 / row.secondsPerPath, row.raysPerSecond,
                    row.imageMean);
      options.say(line);
      report.rows.push_back(row);
    }
  }
  return report;
}

void writeBenchNeeReport(const BenchNeeReport& report, const BenchNeeOptions& options, const std::string& command) {
  std::ostringstream csv;
  csv << "size,triangles,estimator,seconds_per_path,rays_per_second,empty_fraction,image_mean\n";
  for (const BenchNeeRow& r : report.rows)
    csv << r.size << "," << r.triangles << ",\"" << r.estimator << "\"," << r.secondsPerPath << "," << r.raysPerSecond
        << "," << r.emptyFraction << "," << r.imageMean << "\n";
  std::filesystem::create_directories(options.outDir);
  writeFileAtomic(options.outDir / "bench.csv", csv.str());

  std::ostringstream md;
  md << "Command: `" << command << "`  \nDevice: " << report.device << "  \nMedians of " << options.runs
     << " runs, each rendering until its time budget. Cost per path relative to standard NEE on the same scene.\n\n"
     << "| triangles | estimator | paths/s | cost / standard | rays/s | empty connections | image mean |\n"
     << "|---|---|---|---|---|---|---|\n";
  char cell[256];
  for (const BenchNeeRow& r : report.rows) {
    double standard = 0.0;
    for (const BenchNeeRow& s : report.rows)
      if (s.size == r.size && s.estimator == "standard") standard = s.secondsPerPath;
    std::snprintf(cell, sizeof cell, "| %llu | %s | %.3g | %.2fx | %.3g | %.1f%% | %.4g |\n",
                  (unsigned long long)r.triangles, r.estimator.c_str(), 1.0 / r.secondsPerPath,
                  standard > 0 ? r.secondsPerPath / standard : std::nan(""), r.raysPerSecond, 100.0 * r.emptyFraction,
                  r.imageMean);
    md << cell;
  }
  writeFileAtomic(options.outDir / "table.md", md.str());
}

}  // namespace vktg
