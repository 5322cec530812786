#include "bench/bench_optimize.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <random>
#include <sstream>

#include "render/device_scene.h"
#include "grad/gradient.h"
#include "render/planner.h"
#include "render/renderer.h"
#include "grad/term_pilot.h"
#include "opt/loss.h"
#include "opt/plot.h"
#include "scene/primitives.h"
#include "vktg/image_io.h"
#include "vktg/parameter_model.h"

namespace vktg {
namespace {

// An n x n heightfield, 2 m on a side, with smooth bumps, seen from above by a pinhole with a point
// light beside it; one displacement parameter per vertex along +y (as heightfield_heights makes),
// or with `positions` three, along x, y and z (as vertex_positions makes: free-form geometry).
// A box gate around the direct returns, so that all three terms have work: interior, edges
// (silhouettes and shadows of the bumps) and the gate's jumps (path-length boundary).
Scene heightfieldScene(uint32_t n, uint32_t resolution, uint32_t spp, bool positions) {
  Scene scene;
  scene.materials.push_back({"ground", MaterialType::Diffuse, 0.6f});
  std::vector<float> heights(size_t(n) * n);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), z = double(j) / (n - 1);
      heights[size_t(j) * n + i] = float(0.12 * std::sin(7.0 * x) * std::cos(5.0 * z) + 0.05 * std::sin(23.0 * x * z));
    }
  TriangleMesh mesh = makeHeightfield(n, n, 2.0f, 2.0f, heights);
  Shape shape;
  shape.name = "terrain";
  shape.positions = std::move(mesh.positions);
  shape.triangles = std::move(mesh.triangles);
  shape.grid = {n, n};
  scene.shapes.push_back(std::move(shape));
  scene.pointLights.push_back({"laser", glm::vec3(0.4f, 2.0f, 1.2f), 4.0f});
  scene.camera.position = glm::vec3(0.0f, 2.2f, 1.4f);
  scene.camera.lookAt = glm::vec3(0.0f);
  scene.camera.fovY = 45.0f;
  scene.camera.width = scene.camera.height = resolution;
  scene.gate = boxGate(4.4, 5.2);
  scene.render.spp = spp;
  scene.render.maxDepth = 4;
  const VertexExpansion expansion = vertexExpansion(positions ? "vertex_positions" : "heightfield_heights", "terrain");
  for (uint32_t k = 0; k < n * n; ++k)
    for (size_t axis = 0; axis < expansion.suffixes.size(); ++axis) {
      Parameter p;
      // Appended rather than "h" + std::to_string(k), which GCC 12 flags with a false -Wrestrict.
      p.name = expansion.defaultPrefix;
      p.name += std::to_string(k);
      p.name += expansion.suffixes[axis];
      p.kind = ParameterKind::Displace;
      p.target = "terrain";
      p.axis[positions ? int(axis) : 1] = 1.0f;
      p.vertices = {k};
      scene.parameters.push_back(std::move(p));
    }
  return scene;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Where the bench's target puts the n x n heightfield's parameters: heights (y) moved by up to
// 3 cm in a smooth pattern over the vertices; x and z (--positions) by up to a fifth of the grid
// spacing, which keeps the surface from folding over itself (a tangled target would make the SAH
// check rebuild the tree for it, and the renders at θ slower through that tree).
std::vector<double> targetMotion(const Scene& scene, uint32_t n) {
  const double tangential = std::min(0.03, 0.2 * 2.0 / double(n - 1));
  std::vector<double> motion;
  for (const Parameter& p : scene.parameters) {
    const int axis = p.axis.x != 0 ? 0 : p.axis.y != 0 ? 1 : 2;
    motion.push_back((axis == 1 ? 0.03 : tangential) * std::sin(0.37 * double(p.vertices.at(0)) + double(axis) - 1.0));
  }
  return motion;
}

// The images a loss is formed from: I(θ), and a target T rendered with the parameters moved by
// `motion`, so that the gradient the terms add up to is a loss's and the term pilot weighs their
// variances as an optimisation would. Both at 4x the render's samples; the scene is left at θ.
struct LossImages {
  ImageSet atTheta, target;
};

LossImages lossImages(Renderer& renderer, DeviceScene& device, const RenderSetup& setup, const RenderOptions& options,
                      const std::vector<double>& theta, const std::vector<double>& motion) {
  RenderSetup fine = setup;
  fine.settings.spp *= 4;
  fine.settings.seed = 11;
  LossImages images;
  images.atTheta = renderer.render(device, fine, options).mean;
  std::vector<double> moved(theta.size());
  for (size_t k = 0; k < moved.size(); ++k) moved[k] = theta[k] + motion[k];
  device.update(moved, true);
  fine.settings.seed = 12;
  images.target = renderer.render(device, fine, options).mean;
  device.update(theta, true);
  return images;
}

// The adjoint image of the L2 loss of `image` against `target` (opt/loss.h).
ImageSet l2Adjoint(const ImageSet& image, const ImageSet& target) {
  ImageSet adjoint;
  imageLoss(LossSpec{}, image, target, 1.0, &adjoint);
  return adjoint;
}

// The variance of an iteration's whole gradient of the L2 loss against `target` (all terms at `g`'s
// samples, the adjoint image from the iteration's own render) with `passes` chained interior passes
// after a render of 1/passes of the samples, relative to one interior pass after a render of all of
// them: the sum over the heights of each one's variance over kChainedVarianceSeeds iterations with
// independent random numbers, the scene held at θ. The chain's adjoint images hold fewer samples
// than a whole render's (docs/theory.md 4.10), which matters most where I is near T.
double chainedVarianceRatio(Renderer& renderer, DeviceScene& device, const RenderSetup& setup, const RenderOptions& options,
                            uint32_t passes, const ImageSet& target, const GradientOptions& g) {
  constexpr uint32_t kChainedVarianceSeeds = 16;
  auto summedVariance = [&](bool chained) {
    std::vector<std::vector<double>> runs;
    AdjointState state;
    for (uint32_t s = 0; s < kChainedVarianceSeeds; ++s) {
      RenderSetup primal = setup;
      primal.settings.seed = 5000 + 7919 * s;
      if (chained) primal.settings.spp /= passes;
      const ImageSet image = renderer.render(device, primal, options).mean;
      const ImageSet adjoint = l2Adjoint(image, target);
      AdjointView view{setup, {}, &adjoint};
      view.setup.settings.seed = 6000 + 7919 * s;
      AdjointChain chain;
      chain.passes = passes;
      chain.images = {image};
      chain.imageSpp = primal.settings.spp;
      chain.adjointOf = [&](size_t, const ImageSet& soFar) { return l2Adjoint(soFar, target); };
      chain.seedOf = [&](size_t, uint32_t pass) { return view.setup.settings.seed + 1 + pass; };
      runs.push_back(lossGradient(renderer, device, {view}, g, state, chained ? &chain : nullptr).theta);
    }
    const std::vector<double> variance = varianceAcrossRuns(runs);
    return std::accumulate(variance.begin(), variance.end(), 0.0);
  };
  const double plain = summedVariance(false);
  return summedVariance(true) / plain;
}

}  // namespace

BenchOptimizeReport benchOptimize(VulkanContext& context, const BenchOptimizeOptions& options,
                                  const std::function<void(const BenchOptimizeReport&)>& rowDone) {
  BenchOptimizeReport report;
  report.device = context.report().name;
  const uint32_t resolution = options.scaledSide(options.resolution);
  const uint32_t spp = std::max(1u, uint32_t(std::lround(options.spp * options.scale)));
  Renderer renderer(context);
  for (uint32_t n : options.sizes) {
    BenchOptimizeRow row;
    row.size = n;
    const Scene scene = heightfieldScene(n, resolution, spp, options.positions);
    row.parameters = scene.parameters.size();
    row.triangles = scene.triangleCount();
    options.say("heightfield " + std::to_string(n) + "x" + std::to_string(n) + ": " + std::to_string(row.parameters) +
        " parameters, " + std::to_string(row.triangles) + " triangles");
    std::vector<uint32_t> all(scene.parameters.size());
    for (uint32_t k = 0; k < all.size(); ++k) all[k] = k;
    const ParameterModel model(scene, all);
    std::vector<double> theta(all.size(), 0.0);
    auto start = std::chrono::steady_clock::now();
    DeviceScene device(context, model, theta, theta);
    row.buildSeconds = secondsSince(start);

    RenderSetup setup = RenderSetup::of(scene);
    RenderOptions renderOptions;
    renderOptions.memoryBudget = options.memoryBudget;
    const LossImages loss = lossImages(renderer, device, setup, renderOptions, theta, targetMotion(scene, n));
    const ImageSet& target = loss.target;
    const ImageSet adjoint = l2Adjoint(loss.atTheta, target);
    const std::vector<AdjointView> views = {{setup, {}, &adjoint}};
    // The chained iteration: its render at spp / passes, then the gradient whose later interior
    // passes weight by the L2 adjoint of the images so far (the first by the bench's fixed adjoint
    // image, as the unchained gradient is: the same work).
    const uint32_t passes = options.interiorPasses;
    const bool chained = passes > 1 && spp % passes == 0;
    RenderSetup chainedSetup = setup;
    chainedSetup.settings.spp = chained ? spp / passes : spp;
    AdjointChain chain;
    chain.passes = passes;
    chain.imageSpp = chainedSetup.settings.spp;
    chain.adjointOf = [&](size_t, const ImageSet& image) { return l2Adjoint(image, target); };
    chain.seedOf = [&](size_t, uint32_t pass) { return setup.settings.seed + 1 + pass; };
    renderOptions.profile = options.profile;
    struct Variant {
      const char* name;
      double* seconds;
      bool interior, edges, pathLength, sharePaths = true;
      bool pilotSamples = false;  // the edge and boundary terms at the term pilot's counts
      bool chained = false;       // the interior term in options.interiorPasses chained passes
    };
    const Variant variants[] = {{termName(Term::Interior), &row.interiorSeconds, true, false, false},
                                {termName(Term::Edge), &row.edgeSeconds, false, true, false},
                                {termName(Term::PathLength), &row.boundarySeconds, false, false, true},
                                {"all terms", &row.allSeconds, true, true, true},  // every term the options allow
                                {"all terms apart", &row.allApartSeconds, true, true, true, false},
                                {"all terms, pilot's samples", &row.pilotAllSeconds, true, true, true, true, true},
                                {"all terms, pilot's samples, chained", &row.pilotChainedSeconds, true, true, true, true, true, true}};
    auto sayProfile = [&](const std::string& what, const std::map<std::string, double>& passes, const std::string& more = "") {
      if (!options.profile) return;
      double total = 0;
      for (const auto& [pass, ms] : passes) total += ms;
      std::ostringstream text;
      text << "  " << what << ": " << std::fixed << std::setprecision(1) << total << " ms on the device" << more;
      for (const auto& [pass, ms] : passes) text << "\n    " << std::setw(9) << ms << " ms  " << pass;
      options.say(text.str());
    };
    AdjointState state;
    // The term pilot at the starting heights, as `vktg optimize` runs it at its first iteration.
    {
      GradientOptions g;
      g.render = renderOptions;
      g.render.profile = false;
      g.pathLength = options.pathLength;
      AdjointState pilotState;
      const TermAllocation allocation =
          runTermPilot(renderer, device, views, g, pilotState, [](uint32_t round, size_t) { return 1000 + round; });
      row.pilotSppEdge = allocation.sppEdge;
      row.pilotSppBoundary = allocation.sppBoundary;
      row.pilotSppBoundaryCamera = allocation.sppBoundaryCamera;
      row.pilotVarianceRatio = allocation.varianceRatio;
      for (const std::string& line : describeAllocation(allocation)) options.say("  " + line);
    }
    auto withPilot = [&](GradientOptions& g, const Variant& v) {
      if (!v.pilotSamples) return;
      g.sppEdge = row.pilotSppEdge;
      g.sppBoundary = row.pilotSppBoundary;
      g.sppBoundaryCamera = row.pilotSppBoundaryCamera;
    };
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> step(-1e-3, 1e-3);
    // Warm-up: pipelines, films and accumulators are made once, as in an optimisation.
    renderer.render(device, setup, renderOptions);
    for (const Variant& v : variants) {
      if (v.pathLength && !v.interior && !options.pathLength) continue;
      GradientOptions g;
      g.render = renderOptions;
      g.interior = v.interior, g.edges = v.edges, g.pathLength = v.pathLength && options.pathLength;
      g.sharePaths = v.sharePaths;
      withPilot(g, v);
      if (v.chained && !chained) continue;
      if (v.chained) chain.images = {renderer.render(device, chainedSetup, renderOptions).mean};
      lossGradient(renderer, device, views, g, state, v.chained ? &chain : nullptr);
    }
    std::vector<double> update, checked, render, chainedRender;
    std::vector<std::vector<double>> terms(std::size(variants));
    for (uint32_t run = 0; run < options.runs; ++run) {
      for (double& t : theta) t += step(rng);
      start = std::chrono::steady_clock::now();
      device.update(theta, false);
      update.push_back(secondsSince(start));
      start = std::chrono::steady_clock::now();
      device.update(theta, true);  // the same θ again, with the SAH check
      checked.push_back(secondsSince(start));
      start = std::chrono::steady_clock::now();
      const RenderResult primal = renderer.render(device, setup, renderOptions);
      render.push_back(secondsSince(start));
      // Beside the passes' device time: the render's wall clock, and how much of it its batches took
      // (recording, submitting and waiting for their commands), the rest being the host's set-up
      // and read-back.
      if (run + 1 == options.runs)
        sayProfile("render", primal.passMilliseconds,
                   formatReason(", %.1f ms of wall clock, %.1f ms of it in its batches", 1e3 * render.back(),
                                1e3 * primal.stats.seconds));
      if (chained) {
        start = std::chrono::steady_clock::now();
        chain.images = {renderer.render(device, chainedSetup, renderOptions).mean};
        chainedRender.push_back(secondsSince(start));
      }
      for (size_t v = 0; v < std::size(variants); ++v) {
        if (variants[v].pathLength && !variants[v].interior && !options.pathLength) continue;
        GradientOptions g;
        g.render = renderOptions;
        g.interior = variants[v].interior, g.edges = variants[v].edges;
        g.pathLength = variants[v].pathLength && options.pathLength;
        g.sharePaths = variants[v].sharePaths;
        withPilot(g, variants[v]);
        if (variants[v].chained && !chained) continue;
        start = std::chrono::steady_clock::now();
        const LossGradient gradient = lossGradient(renderer, device, views, g, state, variants[v].chained ? &chain : nullptr);
        terms[v].push_back(secondsSince(start));
        if (run + 1 == options.runs) sayProfile(variants[v].name, gradient.passMilliseconds);
      }
    }
    row.updateSeconds = median(update);
    row.checkSeconds = std::max(0.0, median(checked) - row.updateSeconds);
    row.renderSeconds = median(render);
    row.chainedRenderSeconds = chained ? median(chainedRender) : std::nan("");
    for (size_t v = 0; v < std::size(variants); ++v)
      *variants[v].seconds = terms[v].empty() ? std::nan("") : median(terms[v]);
    row.chainedVarianceRatio = row.chainedVarianceRatioAtTarget = std::nan("");
    if (chained) {
      GradientOptions g;
      g.render = renderOptions;
      g.render.profile = false;
      g.pathLength = options.pathLength;
      withPilot(g, variants[std::size(variants) - 1]);
      row.chainedVarianceRatio = chainedVarianceRatio(renderer, device, setup, renderOptions, passes, target, g);
      // Where the optimisation ends: the target is the image at θ itself.
      row.chainedVarianceRatioAtTarget = chainedVarianceRatio(renderer, device, setup, renderOptions, passes, loss.atTheta, g);
    }

    char line[512];
    std::snprintf(line, sizeof line,
                  "  render %.4f s; adjoint gradient of all %llu parameters: interior %.2fx, edges %.2fx, path-length "
                  "boundary %.2fx, all %.2fx (%.2fx tracing the interior and boundary terms apart) the render; update %.4f s (+ %.4f s SAH check); iteration %.2fx",
                  row.renderSeconds, (unsigned long long)row.parameters, row.interiorSeconds / row.renderSeconds,
                  row.edgeSeconds / row.renderSeconds, row.boundarySeconds / row.renderSeconds,
                  row.allSeconds / row.renderSeconds, row.allApartSeconds / row.renderSeconds, row.updateSeconds,
                  row.checkSeconds, row.iterationSeconds() / row.renderSeconds);
    options.say(line);
    std::snprintf(line, sizeof line,
                  "  with the term pilot's samples (edges %g, path-length boundary %g, from the camera %g per pixel; "
                  "predicted variance %.2fx): all terms %.2fx, iteration %.2fx the render",
                  row.pilotSppEdge, row.pilotSppBoundary, row.pilotSppBoundaryCamera, row.pilotVarianceRatio, row.pilotAllSeconds / row.renderSeconds,
                  row.iterationSeconds(true) / row.renderSeconds);
    options.say(line);
    if (chained) {
      std::snprintf(line, sizeof line,
                    "  the same with the interior term in %u chained passes after a render of %u spp (%.4f s): all terms "
                    "%.2fx, iteration %.2fx the render; the gradient's variance %.2fx (measured), %.2fx with the target "
                    "at θ",
                    passes, chainedSetup.settings.spp, row.chainedRenderSeconds, row.pilotChainedSeconds / row.renderSeconds,
                    row.chainedIterationSeconds() / row.renderSeconds, row.chainedVarianceRatio, row.chainedVarianceRatioAtTarget);
      options.say(line);
    }
    // The adjoint figures are kept before the forward-mode contrast, which builds the scene again for
    // every run (tens of seconds at 10^6 heights), so a run stopped there keeps them.
    row.denseSeconds = std::nan("");
    report.rows.push_back(row);
    if (rowDone) rowDone(report);

    // Forward-mode lanes for a few parameters: their passes' time (the scene build excluded).
    BenchOptimizeRow& kept = report.rows.back();
    kept.denseLanes = uint32_t(std::min<uint64_t>(8, row.parameters));
    std::vector<std::string> names;
    for (uint32_t k = 0; k < kept.denseLanes; ++k) names.push_back(scene.parameters[(k * 7919u) % row.parameters].name);
    GradientOptions dense;
    dense.render = renderOptions;
    dense.pathLength = options.pathLength;  // the same terms as the adjoint gradients
    std::vector<double> denseTimes;
    for (uint32_t run = 0; run < options.runs; ++run)
      denseTimes.push_back(renderGradient(renderer, scene, names, dense).stats.seconds);
    kept.denseSeconds = median(denseTimes);
    std::snprintf(line, sizeof line, "  forward lanes for %u parameters %.2fx the render", kept.denseLanes,
                  kept.denseSeconds / kept.renderSeconds);
    options.say(line);
    if (rowDone) rowDone(report);
  }
  return report;
}

void writeBenchOptimizeReport(const BenchOptimizeReport& report, const BenchOptimizeOptions& options, const std::string& command) {
  std::ostringstream csv;
  csv << "size,parameters,triangles,build_s,update_s,check_s,render_s,interior_s,edge_s,boundary_s,all_s,all_apart_s,iteration_s,"
         "pilot_spp_edge,pilot_spp_boundary,pilot_spp_boundary_camera,pilot_variance_ratio,pilot_all_s,pilot_iteration_s,chained_render_s,chained_all_s,chained_iteration_s,chained_variance_ratio,chained_variance_ratio_at_target,dense_lanes,dense_s\n";
  for (const BenchOptimizeRow& r : report.rows)
    csv << r.size << "," << r.parameters << "," << r.triangles << "," << r.buildSeconds << "," << r.updateSeconds << "," << r.checkSeconds << ","
        << r.renderSeconds << "," << r.interiorSeconds << "," << r.edgeSeconds << "," << r.boundarySeconds << ","
        << r.allSeconds << "," << r.allApartSeconds << "," << r.iterationSeconds() << "," << r.pilotSppEdge << ","
        << r.pilotSppBoundary << "," << r.pilotSppBoundaryCamera << "," << r.pilotVarianceRatio << "," << r.pilotAllSeconds << "," << r.iterationSeconds(true)
        << "," << r.chainedRenderSeconds << "," << r.pilotChainedSeconds << "," << r.chainedIterationSeconds() << "," << r.chainedVarianceRatio << "," << r.chainedVarianceRatioAtTarget << "," << r.denseLanes << "," << r.denseSeconds << "\n";
  std::filesystem::create_directories(options.outDir);
  writeFileAtomic(options.outDir / "bench.csv", csv.str());

  std::ostringstream md;
  md << "Command: `" << command << "`  \nDevice: " << report.device << "  \nMedians of " << options.runs
     << " runs. Times in seconds; ratios to the primal render of the same image and samples. An iteration is the update,\n"
     << "an eighth of the SAH check, the render and the gradient of every term run (loss and step are host work).\n"
     << "All terms run: the interior and per-pixel path-length-boundary terms share one trace of the paths; \"apart\":\n"
     << "each traces its own. Pilot: the term pilot's samples per pixel for the edge and path-length-boundary terms\n"
     << "(the latter's connections from path vertices, then from the camera; the interior term's fixed at the\n"
     << "render's) and the variance of the gradient it predicts for them, relative\n"
     << "to every term at the render's samples; then all terms and an iteration at those samples. Chained: the same\n"
     << "with the render at 1/" << options.interiorPasses << " of the samples and the interior term in " << options.interiorPasses
     << " chained passes, and its gradient's variance relative to the unchained one's (measured over 16 seeds; then\n"
     << "with the target at θ, where the optimisation ends).\n\n"
     << "| heightfield | parameters | triangles | render | interior | edges | path-length boundary | all terms run "
        "| all, apart | update | SAH check | iteration | pilot spp (edge, boundary, camera), variance | all terms, pilot "
        "| iteration, pilot | iteration, pilot, chained (variance; with the target at θ) | forward lanes (parameters) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto ratio = [](double seconds, double render) {
    if (std::isnan(seconds)) return std::string("skipped");
    char text[32];
    std::snprintf(text, sizeof text, "%.2fx", seconds / render);
    return std::string(text);
  };
  char cell[512];
  for (const BenchOptimizeRow& r : report.rows) {
    std::snprintf(cell, sizeof cell,
                  "| %ux%u | %llu | %llu | %.4f | %s | %s | %s | **%s** | %s | %.4f | %.4f | %s | %g, %g, %g, %.2fx | %s | **%s** | **%s** (%.2fx, %.2fx) | %s (%u) |\n",
                  r.size, r.size, (unsigned long long)r.parameters, (unsigned long long)r.triangles, r.renderSeconds,
                  ratio(r.interiorSeconds, r.renderSeconds).c_str(), ratio(r.edgeSeconds, r.renderSeconds).c_str(),
                  ratio(r.boundarySeconds, r.renderSeconds).c_str(), ratio(r.allSeconds, r.renderSeconds).c_str(),
                  ratio(r.allApartSeconds, r.renderSeconds).c_str(), r.updateSeconds, r.checkSeconds,
                  ratio(r.iterationSeconds(), r.renderSeconds).c_str(), r.pilotSppEdge, r.pilotSppBoundary,
                  r.pilotSppBoundaryCamera, r.pilotVarianceRatio, ratio(r.pilotAllSeconds, r.renderSeconds).c_str(),
                  ratio(r.iterationSeconds(true), r.renderSeconds).c_str(), ratio(r.chainedIterationSeconds(), r.renderSeconds).c_str(), r.chainedVarianceRatio,
                  r.chainedVarianceRatioAtTarget,
                  ratio(r.denseSeconds, r.renderSeconds).c_str(),
                  r.denseLanes);
    md << cell;
  }
  writeFileAtomic(options.outDir / "table.md", md.str());

  LinePlot plot{"Cost relative to a render (" + report.device + ")", "log10 parameters", "seconds / render", true, {}};
  PlotSeries iteration{"iteration"}, pilotIteration{"iteration, term pilot's samples"},
      chainedIteration{"iteration, pilot's samples, chained interior"}, all{"gradient, all terms run"},
      interior{termName(Term::Interior)}, edges{termName(Term::Edge)}, boundary{termName(Term::PathLength)}, dense{"forward lanes"};
  for (const BenchOptimizeRow& r : report.rows) {
    const double x = std::log10(double(r.parameters));
    for (auto [series, seconds] : {std::pair{&iteration, r.iterationSeconds()}, {&pilotIteration, r.iterationSeconds(true)},
                                   {&chainedIteration, r.chainedIterationSeconds()},
                                   {&all, r.allSeconds},
                                   {&interior, r.interiorSeconds}, {&edges, r.edgeSeconds},
                                   {&boundary, r.boundarySeconds}, {&dense, r.denseSeconds}}) {
      series->x.push_back(x);
      series->y.push_back(seconds / r.renderSeconds);
    }
  }
  plot.series = {iteration, pilotIteration, chainedIteration, all, interior, edges, boundary, dense};
  writeLinePlot(options.outDir / "plot.png", plot);
}

}  // namespace vktg
