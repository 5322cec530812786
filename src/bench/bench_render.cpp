#include "bench/bench_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "bench/bench_common.h"
#include "render/renderer.h"
#include "vktg/error.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

struct BenchCase {
  std::string sceneName;
  Scene scene;
  Gate gate;
  std::string gateName;
  std::vector<float> reference;  // exact (confocal) or cached high-sample render
  uint32_t baseSpp;
};

}  // namespace

Scene confocalPlaneScene(double h, double albedo, double intensity, double halfSize) {
  Scene scene;
  Material m;
  m.name = "plane";
  m.albedo = float(albedo);
  scene.materials.push_back(m);
  Shape plane;
  plane.name = "plane";
  float r = float(halfSize);
  // The plane z = 0, front face toward +z where sensor and light are.
  plane.positions = {{-r, -r, 0}, {r, -r, 0}, {r, r, 0}, {-r, r, 0}};
  plane.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.shapes.push_back(plane);
  scene.pointLights.push_back({"laser", glm::vec3(0, 0, float(h)), float(intensity)});
  scene.camera.type = CameraType::PointSensor;
  scene.camera.position = glm::vec3(0, 0, float(h));
  scene.camera.normal = glm::vec3(0, 0, -1);
  scene.camera.width = scene.camera.height = 1;
  scene.render.maxDepth = 2;
  return scene;
}

double confocalPlaneResponse(double h, double albedo, double intensity, const Gate& gate, double halfSize) {
  // A plane point at distance d from sensor and light receives I h / d^3, reflects rho/pi of it,
  // and is seen under cos = h/d over solid angle h dA / d^3: rho I h^3 / (pi d^7) dA at path
  // length 2d. With dA = 2 pi r dr = 2 pi d dd: M = 2 rho I h^3 * integral of W(2d) d^-6 dd over
  // the disc the square contains (the gates used keep their support inside it).
  double dMax = std::sqrt(h * h + halfSize * halfSize);
  double lo = std::max(h, 0.5 * gate.supportMin());
  double hi = std::min(dMax, 0.5 * gate.supportMax());
  if (!(hi > lo)) return 0.0;
  const int n = 200000;  // Simpson panels over the gate's support: smooth integrand, converged
  double step = (hi - lo) / n, sum = 0;
  for (int i = 0; i <= n; ++i) {
    double d = lo + step * i;
    double f = gate.weight(2 * d) * std::pow(d, -6.0);
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  return 2.0 * albedo * intensity * h * h * h * sum * step / 3.0;
}

BenchRenderReport benchRender(VulkanContext& context, const BenchRenderOptions& options) {
  BenchRenderReport report;
  report.device = context.report().name;
  Renderer renderer(context);
  std::filesystem::create_directories(options.outDir);

  std::vector<BenchCase> cases;
  // Confocal plane (h = 1): exact reference. Gate centre 2.5 m (ring of radius 0.75 m).
  const double h = 1.0, rho = 0.8, intensity = 1.0, half = 10.0, mu = 2.5;
  for (double rel : {1e-1, 1e-2, 1e-3}) {
    BenchCase c{"confocal", confocalPlaneScene(h, rho, intensity, half), gaussianGate(mu, rel * mu), "", {}, 512};
    char name[64];
    std::snprintf(name, sizeof name, "gaussian s/m=%.0e", rel);
    c.gateName = name;
    c.reference = {float(confocalPlaneResponse(h, rho, intensity, c.gate, half))};
    cases.push_back(std::move(c));
  }
  {
    BenchCase c{"confocal", confocalPlaneScene(h, rho, intensity, half), boxGate(2.4, 2.6), "box 2.4-2.6 m", {}, 512};
    c.reference = {float(confocalPlaneResponse(h, rho, intensity, c.gate, half))};
    cases.push_back(std::move(c));
  }
  // The default Cornell box at 16x16 with a cached high-sample reference (ellipsoidal NEE for the
  // narrow gates, where it converges fastest; standard for the box).
  for (double rel : {1e-1, 1e-2, 1e-3}) {
    BenchCase c{"cornell", defaultScene(), gaussianGate(5.0, rel * 5.0), "", {}, 4};
    char name[64];
    std::snprintf(name, sizeof name, "gaussian s/m=%.0e", rel);
    c.gateName = name;
    cases.push_back(std::move(c));
  }
  cases.push_back({"cornell", defaultScene(), boxGate(4.5, 5.5), "box 4.5-5.5 m", {}, 4});

  const uint32_t referenceSpp = uint32_t(std::max(64.0, 8192 * options.scale));
  for (BenchCase& c : cases) {
    c.scene.gate = c.gate;
    if (c.sceneName == "cornell") {
      c.scene.camera.width = c.scene.camera.height = 16;
      c.scene.render.maxDepth = 8;
      char file[128];
      std::snprintf(file, sizeof file, "reference-%s-%g-%g-%g.exr", c.sceneName.c_str(), c.gate.mu, c.gate.sigma,
                    c.gate.b);
      std::filesystem::path cached = options.outDir / file;
      if (std::filesystem::exists(cached)) {
        c.reference = readExr(cached).layers.at(0).pixels;
      } else {
        Scene ref = c.scene;
        ref.render.spp = referenceSpp;
        ref.render.seed = 0xbe4c4u;
        RenderOptions ro;
        ro.memoryBudget = options.memoryBudget;
        ro.nee = c.gate.type == GateType::Box ? NeeMode::Standard : NeeMode::Ellipsoidal;
        options.say("reference " + c.sceneName + " " + c.gateName + " (" + std::to_string(ref.render.spp) + " spp)");
        RenderResult r = renderer.render(ref, ro);
        c.reference = r.mean.layers[0].pixels;
        writeExr(cached, r.mean);
      }
    }
    for (NeeMode nee : {NeeMode::Standard, NeeMode::Ellipsoidal}) {
      auto renderAt = [&](uint32_t spp, uint32_t seed, bool profile = false) {
        Scene s = c.scene;
        s.render.spp = spp;
        s.render.seed = seed;
        RenderOptions ro;
        ro.memoryBudget = options.memoryBudget;
        ro.profile = profile;
        ro.nee = nee;
        return renderer.render(s, ro);
      };
      renderAt(1, 0);  // warm-up: drivers may compile pipelines at first use; keep that out of the timings
      const uint32_t firstSpp =
          firstLadderSpp(c.baseSpp, options, [&](uint32_t spp) { return renderAt(spp, 999).stats.seconds; });
      const bool renderedReference = c.sceneName == "cornell";  // the confocal plane's is exact
      if (renderedReference && (uint64_t(firstSpp) << options.ladderSteps) * 4 > referenceSpp)
        options.say("warning: the curve reaches " + std::to_string(firstSpp << options.ladderSteps) +
                    " spp, within 4x of the reference's " + std::to_string(referenceSpp) +
                    ": its relMSE includes the reference's own error (raise --scale or lower --point-seconds)");
      for (uint32_t step = 0; step <= options.ladderSteps; ++step) {
        const uint32_t spp = firstSpp << step;
        std::vector<double> times, errors, pathRates, rayRates;
        for (uint32_t run = 0; run < options.runs; ++run) {
          RenderResult r = renderAt(spp, 1000 + run);
          times.push_back(r.stats.seconds);
          errors.push_back(relMse(r.mean.layers[0].pixels, c.reference));
          pathRates.push_back(double(r.stats.paths) / r.stats.seconds);
          rayRates.push_back(double(r.stats.extensionRays + r.stats.shadowRays) / r.stats.seconds);
          report.peakDeviceMiB = std::max(report.peakDeviceMiB, double(r.stats.deviceBytes) / (1 << 20));
        }
        // The pass table: one more render of the last point, timed per pass (timestamps cost a few
        // ms per render on lavapipe, so the points themselves are not profiled).
        if (step == options.ladderSteps && &c == &cases.back() && nee == NeeMode::Standard) {
          const RenderResult r = renderAt(spp, 1000, true);
          double total = 0;
          for (const auto& [name, ms] : r.passMilliseconds) total += ms;
          for (const auto& [name, ms] : r.passMilliseconds) {
            char line[160];
            std::snprintf(line, sizeof line, "| %s | %.1f | %.1f%% |", name.c_str(), ms, 100.0 * ms / total);
            report.passTable.push_back(line);
          }
        }
        BenchRenderPoint p{c.sceneName, c.gateName, neeModeName(nee), spp, median(times), median(errors),
                           median(pathRates), median(rayRates)};
        char line[256];
        std::snprintf(line, sizeof line, "%-8s %-18s %-11s spp %6u  %8.3f s  relMSE %.3e", p.scene.c_str(),
                      p.gate.c_str(), p.estimator.c_str(), spp, p.seconds, p.relMse);
        options.say(line);
        report.points.push_back(p);
      }
    }
  }

  // What ending paths at the gate's support saves: the same render with and without the cutoff.
  {
    Scene s = defaultScene();
    s.camera.width = s.camera.height = 16;
    s.render.spp = uint32_t(std::max(4.0, 64 * options.scale));
    s.gate = boxGate(3.5, 4.5);
    RenderOptions with, without;
    with.memoryBudget = without.memoryBudget = options.memoryBudget;
    without.gateCutoff = false;
    renderer.render(s, without);  // warm-up
    RenderResult a = renderer.render(s, with);
    RenderResult b = renderer.render(s, without);
    char text[512];
    std::snprintf(text, sizeof text,
                  "default scene, box gate [3.5, 4.5] m, 16x16, %u spp: %llu extension + %llu shadow rays with the "
                  "cutoff (%.3f s) vs %llu + %llu without (%.3f s): %.1f%% of the rays saved, %llu paths ended by the gate",
                  s.render.spp, (unsigned long long)a.stats.extensionRays, (unsigned long long)a.stats.shadowRays,
                  a.stats.seconds, (unsigned long long)b.stats.extensionRays, (unsigned long long)b.stats.shadowRays,
                  b.stats.seconds,
                  100.0 * (1.0 - double(a.stats.extensionRays + a.stats.shadowRays) /
                                     double(b.stats.extensionRays + b.stats.shadowRays)),
                  (unsigned long long)a.stats.endedByGate);
    report.cutoffSummary = text;
    options.say(text);
  }
  report.peakHostMiB = peakHostMiB();
  return report;
}

void writeBenchRenderReport(const BenchRenderReport& report, const BenchRenderOptions& options, const std::string& command) {
  std::ostringstream csv;
  csv << "scene,gate,estimator,spp,seconds,relmse,paths_per_s,rays_per_s\n";
  for (const auto& p : report.points)
    csv << p.scene << "," << p.gate << "," << p.estimator << "," << p.spp << "," << p.seconds << "," << p.relMse << ","
        << p.pathsPerSecond << "," << p.raysPerSecond << "\n";
  std::filesystem::path csvPath = options.outDir / "bench.csv";
  writeFileAtomic(csvPath, csv.str());

  std::ostringstream md;
  md << "Command: `" << command << "`  \nDevice: " << report.device << "  \n"
     << "Medians of " << options.runs << " runs per point (different seeds). relMSE against the exact response "
     << "(confocal) or a cached high-sample render (cornell).\n\n";
  // Efficiency = relMSE x time (lower is better; constant along a curve for an unbiased
  // estimator once its variance dominates). Summary: the median over each curve, and the ratio.
  md << "Summary (median of relMSE x time over each curve; speed-up = standard / ellipsoidal):\n\n"
        "| scene | gate | standard | ellipsoidal | speed-up of ellipsoidal |\n|---|---|---|---|---|\n";
  std::vector<std::pair<std::string, std::string>> cases;
  for (const auto& p : report.points)
    if (std::find(cases.begin(), cases.end(), std::make_pair(p.scene, p.gate)) == cases.end())
      cases.emplace_back(p.scene, p.gate);
  for (const auto& [scene, gate] : cases) {
    std::vector<double> standard, ellipsoidal;
    for (const auto& p : report.points)
      if (p.scene == scene && p.gate == gate)
        (p.estimator == std::string("standard") ? standard : ellipsoidal).push_back(p.relMse * p.seconds);
    if (standard.empty() || ellipsoidal.empty()) continue;
    double s = median(standard), e = median(ellipsoidal);
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %s | %.3e | %.3e | %.3gx |\n", scene.c_str(), gate.c_str(), s, e, s / e);
    md << line;
  }
  md << "\nAll points:\n\n";
  md << "| scene | gate | estimator | spp | time (s) | relMSE | relMSE x time | paths/s | rays/s |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& p : report.points) {
    char line[320];
    std::snprintf(line, sizeof line, "| %s | %s | %s | %u | %.3f | %.3e | %.3e | %.3g | %.3g |\n", p.scene.c_str(),
                  p.gate.c_str(), p.estimator.c_str(), p.spp, p.seconds, p.relMse, p.relMse * p.seconds,
                  p.pathsPerSecond, p.raysPerSecond);
    md << line;
  }
  md << "\nGPU time per pass (cornell, box gate, standard NEE, largest spp):\n\n| pass | ms | share |\n|---|---|---|\n";
  for (const auto& l : report.passTable) md << l << "\n";
  md << "\nGate cutoff: " << report.cutoffSummary << "\n\n";
  char mem[160];
  std::snprintf(mem, sizeof mem, "Peak device memory of a render: %.1f MiB; peak host memory (RSS): %.1f MiB.\n",
                report.peakDeviceMiB, report.peakHostMiB);
  md << mem;
  writeFileAtomic(options.outDir / "table.md", md.str());

  plotBenchCsv(csvPath, options.outDir / "plot.png", options.log);
}

}  // namespace vktg
