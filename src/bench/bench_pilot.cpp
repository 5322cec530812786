#include "bench/bench_pilot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "bench/bench_render.h"
#include "render/nee_pilot.h"
#include "render/renderer.h"
#include "vktg/error.h"

namespace vktg {
namespace {

struct PilotCase {
  std::string sceneName, gateName;
  Scene scene;
};

std::string gateLabel(const char* kind, double rel) {
  char text[64];
  std::snprintf(text, sizeof text, "%s s/m=%.0e", kind, rel);
  return text;
}

const NeeMode kEstimators[] = {NeeMode::Standard, NeeMode::Ellipsoidal, NeeMode::Mis};

}  // namespace

BenchPilotReport benchPilot(VulkanContext& context, const BenchOptions& options) {
  if (options.runs < 2) throw Error("bench pilot: --runs must be at least 2 (the measured relMSE is an across-seed variance)");
  BenchPilotReport report;
  report.device = context.report().name;
  Renderer renderer(context);
  std::filesystem::create_directories(options.outDir);

  std::vector<PilotCase> cases;
  const uint32_t side = options.scaledSide(64);
  for (double rel : {1e-1, 1e-2, 1e-3}) {
    PilotCase c{"cornell", gateLabel("gaussian", rel), defaultScene()};
    c.scene.gate = gaussianGate(5.0, rel * 5.0);
    cases.push_back(std::move(c));
  }
  cases.push_back({"cornell", "box 4.5-5.5 m", defaultScene()});
  cases.back().scene.gate = boxGate(4.5, 5.5);
  for (PilotCase& c : cases) {
    c.scene.camera.width = c.scene.camera.height = side;
    c.scene.render.spp = std::max(kPilotMinRenderSpp, uint32_t(std::lround(1024 * options.scale)));
  }
  for (double rel : {1e-1, 1e-2}) {
    PilotCase c{"confocal", gateLabel("gaussian", rel), confocalPlaneScene(1.0, 0.8, 1.0, 10.0)};
    c.scene.gate = gaussianGate(2.5, rel * 2.5);
    c.scene.render.spp = std::max(kPilotMinRenderSpp, uint32_t(std::lround(65536 * options.scale)));
    cases.push_back(std::move(c));
  }

  for (const PilotCase& c : cases) {
    options.say("pilot " + c.sceneName + " " + c.gateName + " (" + std::to_string(c.scene.render.spp) + " spp)");
    DeviceScene scene(context, c.scene);
    const RenderSetup setup = RenderSetup::of(c.scene);
    RenderOptions base;
    base.memoryBudget = options.memoryBudget;
    const auto pilotStart = std::chrono::steady_clock::now();
    // The whole pilot, even where `vktg render` would stop it as not paying: its predictions are what is measured.
    const PilotDecision decision = runNeePilot(renderer, scene, setup, base, false);
    BenchPilotCase summary{c.sceneName, c.gateName};
    summary.pilotSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pilotStart).count();
    summary.ruleChoice = neeModeName(planRender(setup, scene.prepared(), NeeMode::Auto).nee);
    summary.pilotChoice = decision.choice ? neeModeName(*decision.choice) : summary.ruleChoice;
    summary.pays = decision.pays;

    // Every estimator `runs` times with its own seeds; the pooled image of all of them is the reference.
    std::vector<std::vector<std::vector<float>>> images(3);
    std::vector<double> seconds[3];
    for (uint32_t run = 0; run < options.runs; ++run)
      for (uint32_t k = 0; k < 3; ++k) {
        RenderSetup s = setup;
        s.settings.seed = 1000 + 7 * run + k;
        RenderOptions o = base;
        o.nee = kEstimators[k];
        RenderResult r = renderer.render(scene, s, o);
        images[k].push_back(r.mean.allPixels());
        seconds[k].push_back(r.stats.seconds);
      }
    const size_t pixels = images[0][0].size();
    std::vector<float> pooled(pixels, 0.0f);
    for (const auto& estimator : images)
      for (const auto& image : estimator)
        for (size_t i = 0; i < pixels; ++i) pooled[i] += image[i] / float(3 * options.runs);
    double best = INFINITY;
    std::vector<double> efficiency(3);
    for (uint32_t k = 0; k < 3; ++k) {
      // The across-seed variance of each pixel: one render's squared error, its estimator being unbiased.
      const std::vector<double> across = varianceAcrossRuns(images[k]);
      const std::vector<float> variance(across.begin(), across.end());
      BenchPilotRow row{c.sceneName, c.gateName, neeModeName(kEstimators[k]), c.scene.render.spp};
      const PilotEstimate& predicted = decision.estimates[k];
      row.predictedSeconds = predicted.seconds;
      row.predictedRelMse = predicted.relMse;
      row.excluded = predicted.excluded;
      row.measuredSeconds = median(seconds[k]);
      row.measuredRelMse = expectedRelMse(variance, pooled);
      efficiency[k] = row.measuredSeconds * row.measuredRelMse;
      if (efficiency[k] < best) {
        best = efficiency[k];
        summary.measuredBest = row.estimator;
      }
      report.rows.push_back(row);
    }
    for (uint32_t k = 0; k < 3; ++k) {
      if (summary.pilotChoice == neeModeName(kEstimators[k])) summary.pilotRegret = efficiency[k] / best;
      if (summary.ruleChoice == neeModeName(kEstimators[k])) summary.ruleRegret = efficiency[k] / best;
    }
    report.cases.push_back(summary);
  }
  return report;
}

void writeBenchPilotReport(const BenchPilotReport& report, const BenchOptions& options, const std::string& command) {
  std::filesystem::create_directories(options.outDir);
  std::ostringstream csv;
  csv << "scene,gate,estimator,spp,predicted_seconds,predicted_relmse,measured_seconds,measured_relmse,excluded\n";
  for (const BenchPilotRow& r : report.rows)
    csv << r.scene << "," << r.gate << "," << r.estimator << "," << r.spp << "," << r.predictedSeconds << ","
        << r.predictedRelMse << "," << r.measuredSeconds << "," << r.measuredRelMse << "," << (r.excluded ? 1 : 0) << "\n";
  writeFileAtomic(options.outDir / "bench.csv", csv.str());

  std::ostringstream md;
  md << "`" << command << "` on " << report.device << ". Per case, the pilot (1/" << kPilotFraction
     << " of the render's samples per estimator) predicts each estimator's time and relMSE for the render; each estimator "
        "then renders it "
     << options.runs << " times, and the measured relMSE is the across-seed variance of each pixel over the pooled image "
                        "(median seconds). Regret: measured relMSE x time of the choice over the best one's. --pilot auto: whether `vktg "
        "render` would run the whole pilot or let the rule decide.\n\n"
     << "| scene | gate | pilot's choice | regret | rule's choice | regret | measured best | pilot (s) | --pilot auto |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  char line[512];
  for (const BenchPilotCase& c : report.cases) {
    std::snprintf(line, sizeof line, "| %s | %s | %s | %.2fx | %s | %.2fx | %s | %.2f | %s |\n", c.scene.c_str(),
                  c.gate.c_str(), c.pilotChoice.c_str(), c.pilotRegret, c.ruleChoice.c_str(), c.ruleRegret,
                  c.measuredBest.c_str(), c.pilotSeconds, c.pays ? "pilot" : "rule (pilot would not pay)");
    md << line;
  }
  md << "\n| scene | gate | estimator | spp | predicted s | measured s | predicted relMSE | measured relMSE | "
        "predicted relMSE x time | measured relMSE x time |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BenchPilotRow& r : report.rows) {
    std::snprintf(line, sizeof line, "| %s | %s | %s%s | %u | %.3g | %.3g | %.3g | %.3g | %.3g | %.3g |\n", r.scene.c_str(),
                  r.gate.c_str(), r.estimator.c_str(), r.excluded ? " (excluded)" : "", r.spp, r.predictedSeconds,
                  r.measuredSeconds, r.predictedRelMse, r.measuredRelMse, r.predictedSeconds * r.predictedRelMse,
                  r.measuredSeconds * r.measuredRelMse);
    md << line;
  }
  writeFileAtomic(options.outDir / "table.md", md.str());
  options.say(md.str());
}

}  // namespace vktg
