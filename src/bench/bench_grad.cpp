#include "bench/bench_grad.h"

#include <cstdio>
#include <sstream>

#include "bench/bench_common.h"
#include "bench/bench_render.h"
#include "grad/gradient.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

constexpr double kH = 1.0, kAlbedo = 0.8, kIntensity = 1.0, kHalf = 10.0;

// The confocal plane with one parameter: the plane moving away from the sensor (dh/dθ = 1).
Scene confocalWithDistance(const Gate& gate) {
  Scene scene = confocalPlaneScene(kH, kAlbedo, kIntensity, kHalf);
  scene.gate = gate;
  Parameter p;
  p.name = "plane_h";
  p.kind = ParameterKind::Translate;
  p.target = "plane";
  p.axis = glm::vec3(0, 0, -1);
  scene.parameters.push_back(p);
  return scene;
}

// dM/dh of the exact response by a central difference of the quadrature (double; the step's
// truncation error, ~1e-8 relative, is far below any Monte Carlo error measured here).
double exactDerivative(const Gate& gate) {
  const double step = 1e-4;
  return (confocalPlaneResponse(kH + step, kAlbedo, kIntensity, gate, kHalf) -
          confocalPlaneResponse(kH - step, kAlbedo, kIntensity, gate, kHalf)) /
         (2 * step);
}

// The error of a signed derivative image against its reference: sum (x - r)^2 / sum r^2 (a
// per-pixel relative error is meaningless where the derivative crosses zero).
double normalizedMse(const std::vector<float>& x, const std::vector<float>& ref) {
  double num = 0, den = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    num += (double(x[i]) - ref[i]) * (double(x[i]) - ref[i]);
    den += double(ref[i]) * ref[i];
  }
  return den > 0 ? num / den : num;
}

// The default scene (box gate) with its short box translated sideways: moving silhouettes and
// shadows for the edge term, and a material's albedo beside it for the cost comparison.
Scene defaultSceneWithParameters(uint32_t resolution, uint32_t spp) {
  Scene scene = defaultScene();
  scene.camera.width = scene.camera.height = resolution;
  scene.render.spp = spp;
  scene.gate = boxGate(4.0, 5.5);
  Parameter albedo;
  albedo.name = "albedo";
  albedo.kind = ParameterKind::Albedo;
  albedo.target = scene.materials.at(scene.shapes.at(0).material).name;
  scene.parameters.push_back(albedo);
  Parameter move;
  move.name = "move";
  move.kind = ParameterKind::Translate;
  move.target = "short_box";
  move.axis = glm::vec3(1, 0, 0);
  scene.parameters.push_back(move);
  return scene;
}

struct Estimator {
  std::string name;
  NeeMode nee;
  AntitheticMode antithetic;
};

}  // namespace

BenchGradReport benchGrad(VulkanContext& context, const BenchGradOptions& options) {
  BenchGradReport report;
  report.device = context.report().name;
  Renderer renderer(context);
  auto record = [&](const BenchGradPoint& p) {
    char line[256];
    std::snprintf(line, sizeof line, "%-18s %-32s spp %6u  %8.3f s  relMSE %.3e", p.gate.c_str(), p.estimator.c_str(),
                  p.spp, p.seconds, p.relMse);
    options.say(line);
    report.points.push_back(p);
  };

  struct Case {
    Gate gate;
    std::string name;
    std::vector<Estimator> estimators;
  };
  std::vector<Case> cases;
  const double mu = 2.5;
  for (double rel : {1e-1, 1e-2, 1e-3}) {
    char name[64];
    std::snprintf(name, sizeof name, "gaussian s/m=%.0e", rel);
    cases.push_back({gaussianGate(mu, rel * mu), name,
                     {{"standard", NeeMode::Standard, AntitheticMode::Off},
                      {"ellipsoidal", NeeMode::Ellipsoidal, AntitheticMode::Off},
                      {"ellipsoidal+antithetic", NeeMode::Ellipsoidal, AntitheticMode::On}}});
  }
  cases.push_back({boxGate(2.4, 2.6), "box 2.4-2.6 m",
                   {{"interior+pathlength (standard)", NeeMode::Standard, AntitheticMode::Off},
                    {"interior+pathlength (ellipsoidal)", NeeMode::Ellipsoidal, AntitheticMode::Off}}});

  for (const Case& c : cases) {
    Scene scene = confocalWithDistance(c.gate);
    float reference = float(exactDerivative(c.gate));
    for (const Estimator& e : c.estimators) {
      GradientOptions go;
      go.render.memoryBudget = options.memoryBudget;
      go.render.nee = e.nee;
      go.antithetic = e.antithetic;
      auto gradientAt = [&](uint32_t spp, uint32_t seed) {
        Scene s = scene;
        s.render.spp = spp;
        s.render.seed = seed;
        return renderGradient(renderer, s, {"plane_h"}, go);
      };
      gradientAt(1, 0);  // warm-up: drivers may compile pipelines at first use; keep it out of the timings
      const uint32_t firstSpp =
          firstLadderSpp(512, options, [&](uint32_t spp) { return gradientAt(spp, 1999).stats.seconds; });
      for (uint32_t step = 0; step <= options.ladderSteps; ++step) {
        const uint32_t spp = firstSpp << step;
        std::vector<double> times, errors;
        for (uint32_t run = 0; run < options.runs; ++run) {
          GradientResult g = gradientAt(spp, 2000 + run);
          times.push_back(g.stats.seconds);
          errors.push_back(relMse(g.total.derivatives[0].layers[0].pixels, {reference}));
        }
        record({"confocal", c.name, e.name, spp, median(times), median(errors)});
      }
    }
  }

  // The path-length-boundary term alone, plain (one jump per sample) against antithetic pairs
  // (both jumps, shared random numbers), for narrow box gates around 2.5 m. The light sits 1 m from
  // the sensor so that each jump's ellipse carries a varying integrand (on the confocal plane it
  // is constant and the pairs cancel to rounding); reference: pairs with 16 times the largest budget.
  for (double rel : {1e-1, 1e-2, 1e-3}) {
    Scene scene = confocalWithDistance(boxGate(mu * (1 - rel), mu * (1 + rel)));
    scene.pointLights.at(0).position.x += 1.0f;
    char name[64];
    std::snprintf(name, sizeof name, "box half-width/centre=%.0e (boundary term)", rel);
    GradientOptions go;
    go.render.memoryBudget = options.memoryBudget;
    go.render.nee = NeeMode::Ellipsoidal;
    go.interior = go.edges = false;
    go.antithetic = AntitheticMode::On;
    const uint32_t firstSpp = firstLadderSpp(512, options, [&](uint32_t spp) {
      Scene s = scene;
      s.render.spp = spp;
      return renderGradient(renderer, s, {"plane_h"}, go).stats.seconds;
    });
    Scene refScene = scene;
    refScene.render.spp = (firstSpp << options.ladderSteps) * 16;
    refScene.render.seed = 4000;
    float reference = renderGradient(renderer, refScene, {"plane_h"}, go).total.derivatives[0].layers[0].pixels[0];
    for (AntitheticMode mode : {AntitheticMode::Off, AntitheticMode::On}) {
      go.antithetic = mode;
      for (uint32_t step = 0; step <= options.ladderSteps; ++step) {
        std::vector<double> times, errors;
        for (uint32_t run = 0; run < options.runs; ++run) {
          Scene s = scene;
          s.render.spp = firstSpp << step;
          s.render.seed = 5000 + run;
          GradientResult g = renderGradient(renderer, s, {"plane_h"}, go);
          times.push_back(g.stats.seconds);
          errors.push_back(relMse(g.total.derivatives[0].layers[0].pixels, {reference}));
        }
        record({"separated", name, mode == AntitheticMode::On ? "antithetic" : "plain", firstSpp << step,
                median(times), median(errors)});
      }
    }
  }

  // The edge term against its budget: d image / d(short box x) of the default scene, 32x32, its
  // error against a reference with 16 times the ladder's largest budget.
  {
    Scene scene = defaultSceneWithParameters(32, 1);
    GradientOptions go;
    go.render.memoryBudget = options.memoryBudget;
    go.interior = go.pathLength = false;
    const uint32_t firstSpp = firstLadderSpp(16, options, [&](uint32_t spp) {
      go.sppEdge = spp;
      return renderGradient(renderer, scene, {"move"}, go).stats.seconds;
    });
    go.sppEdge = (firstSpp << options.ladderSteps) * 16;
    std::vector<float> reference = renderGradient(renderer, scene, {"move"}, go).total.derivatives[0].layers[0].pixels;
    for (uint32_t step = 0; step <= options.ladderSteps; ++step) {
      go.sppEdge = firstSpp << step;
      std::vector<double> times, errors;
      for (uint32_t run = 0; run < options.runs; ++run) {
        Scene s = scene;
        s.render.seed = 3000 + run;
        GradientResult g = renderGradient(renderer, s, {"move"}, go);
        times.push_back(g.stats.seconds);
        errors.push_back(normalizedMse(g.total.derivatives[0].layers[0].pixels, reference));
      }
      record({"default 32x32", "box 4-5.5 m (edge term)", "edge samples", firstSpp << step, median(times), median(errors)});
    }
  }

  // Cost of a gradient relative to the render at equal samples: the default scene with two
  // parameters (a material's albedo and the short box's translation), box gate.
  {
    Scene scene = defaultSceneWithParameters(32, uint32_t(std::max(4.0, 32 * options.scale)));
    RenderOptions ro;
    ro.memoryBudget = options.memoryBudget;
    GradientOptions interiorOnly, all;
    interiorOnly.render = all.render = ro;
    interiorOnly.pathLength = interiorOnly.edges = false;
    renderer.render(scene, ro);
    renderGradient(renderer, scene, {"albedo", "move"}, all);
    std::vector<double> primal, interior, total;
    for (uint32_t run = 0; run < options.runs; ++run) {
      primal.push_back(renderer.render(scene, ro).stats.seconds);
      interior.push_back(renderGradient(renderer, scene, {"albedo", "move"}, interiorOnly).stats.seconds);
      total.push_back(renderGradient(renderer, scene, {"albedo", "move"}, all).stats.seconds);
    }
    char line[512];
    std::snprintf(line, sizeof line,
                  "default scene 32x32, %u spp, box gate [4, 5.5] m, 2 parameters: render %.3f s, gradient interior "
                  "term %.3f s (%.2fx), interior + edge + path-length boundary (as many edge and boundary samples "
                  "per pixel) %.3f s (%.2fx)",
                  scene.render.spp, median(primal), median(interior), median(interior) / median(primal), median(total),
                  median(total) / median(primal));
    report.costLines.push_back(line);
    options.say(line);
  }
  return report;
}

void writeBenchGradReport(const BenchGradReport& report, const BenchGradOptions& options, const std::string& command) {
  std::filesystem::create_directories(options.outDir);
  std::ostringstream csv;
  csv << "scene,gate,estimator,spp,seconds,relmse\n";
  for (const auto& p : report.points)
    csv << p.scene << "," << p.gate << "," << p.estimator << "," << p.spp << "," << p.seconds << "," << p.relMse << "\n";
  std::filesystem::path csvPath = options.outDir / "bench.csv";
  writeFileAtomic(csvPath, csv.str());

  std::ostringstream md;
  md << "Command: `" << command << "`  \nDevice: " << report.device << "  \nMedians of " << options.runs
     << " runs per point. d M / d h of the confocal plane (h = 1 m) against its exact value; the path-length-"
        "boundary term with the light 1 m from the sensor against antithetic pairs with 16 times the largest "
        "budget; the edge term of the "
        "default scene (short box moved sideways) against a reference with 16 times the largest budget, error "
        "sum (x - r)^2 / sum r^2.\n\n"
     << "| gate | estimator | median relMSE x time | vs standard or plain |\n|---|---|---|---|\n";
  std::vector<std::pair<std::string, std::string>> curves;
  for (const auto& p : report.points)
    if (std::find(curves.begin(), curves.end(), std::make_pair(p.gate, p.estimator)) == curves.end())
      curves.emplace_back(p.gate, p.estimator);
  for (const auto& [gate, estimator] : curves) {
    std::vector<double> eff, base;
    for (const auto& p : report.points) {
      if (p.gate != gate) continue;
      if (p.estimator == estimator) eff.push_back(p.relMse * p.seconds);
      if (p.estimator.find("standard") != std::string::npos || p.estimator == "plain")
        base.push_back(p.relMse * p.seconds);
    }
    char line[256];
    if (base.empty())  // no standard estimator of this quantity to compare with
      std::snprintf(line, sizeof line, "| %s | %s | %.3e | - |\n", gate.c_str(), estimator.c_str(), median(eff));
    else
      std::snprintf(line, sizeof line, "| %s | %s | %.3e | %.3gx |\n", gate.c_str(), estimator.c_str(), median(eff),
                    median(base) / median(eff));
    md << line;
  }
  md << "\n";
  for (const auto& l : report.costLines) md << l << "\n";
  md << "\n| gate | estimator | spp | time (s) | relMSE |\n|---|---|---|---|---|\n";
  for (const auto& p : report.points) {
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %s | %u | %.3f | %.3e |\n", p.gate.c_str(), p.estimator.c_str(), p.spp,
                  p.seconds, p.relMse);
    md << line;
  }
  writeFileAtomic(options.outDir / "table.md", md.str());
  plotBenchCsv(csvPath, options.outDir / "plot.png", options.log);
}

}  // namespace vktg
