// `vktg render`: renders a time-gated image (or transient stack) and writes EXR + PNG (+ npy).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/mpi_world.h"
#include "cli/scan_capture.h"
#include "cli/scan_views.h"
#include "render/nee_pilot.h"
#include "render/renderer.h"
#include "vktg/image_io.h"

namespace vktg::cli {

const CommandSpec& renderSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "render";
    s.usage = "render [SCENE] [options]";
    s.description =
        "Renders what a time-of-flight camera sees through a time gate. SCENE is a .json scene, a .gltf/.glb\n"
        "file, a Mitsuba 3 / mitransient .xml scene (-D NAME=VALUE sets its $NAME; an nlos_capture_meter renders\n"
        "its whole grid of wall points as a scan), or omitted for the built-in default (a Cornell-box-like room\n"
        "behind a box gate). Writes an EXR\n"
        "(one layer per bin for a transient stack) and a PNG preview. With NEE left to the planner and a gate of\n"
        "finite extent, from 256 spp, a pilot at 1/32 of the samples per estimator picks standard, ellipsoidal or\n"
        "MIS NEE by the lowest predicted relMSE x time on this device where the render is long enough for that to\n"
        "pay (--explain prints the numbers); give --nee to fix the estimator.";
    s.options = sceneOverrideOptions();
    s.options.push_back({"--out", "FILE.exr",
                         "output image (default out/render.exr); the PNG goes beside it. FILE.hdf5 or FILE.h5 with --scan: the "
                         "scan's transients as an NLOS capture in tal's HDF5 layout instead of the EXR (a point sensor and a "
                         "bins gate; docs/scene-format.md, NLOS captures)"});
    s.options.push_back({"--npy", "", "also write FILE.npy, float32 of shape (H, W, T)"});
    s.options.push_back(scanOption("the image"));
    s.options.push_back({"--profile", "", "print GPU time per pass"});
    s.options.push_back({"--explain", "", "print the planner's choices and why"});
    s.options.push_back({"--pilot", "WHEN",
                         "auto | on | off: with NEE left to the planner, pick it by a timed pilot where that pays (auto: the "
                         "pilot would take at most 1/4 of the render), always (on), or never (off: the gate-width rule)"});
    s.options.push_back({"--no-gate-cutoff", "", "keep tracing paths past the gate (to measure what the cutoff saves)"});
    for (auto& o : deviceOptions()) s.options.push_back(o);
    s.examples =
        "  vktg render                                   # default scene, out/render.exr + out/render.png\n"
        "  vktg render scenes/cornell_box.json --gate box:3.5,4.5 --spp 256\n"
        "  vktg render scenes/cornell_box.json --gate bins:3,0.1,40 --out out/stack.exr --npy\n"
        "  vktg render scenes/confocal_plane.json --gate gaussian:2,0.002 --explain\n"
        "  vktg render experiments/confocal_scan/scene.json --scan experiments/confocal_scan/scan.json --npy\n"
        "  vktg render experiments/confocal_scan/scene.json --scan experiments/confocal_scan/scan.json --out out/scan.hdf5\n"
        "  vktg render scenes/default_room.xml -D spp=256 -D resolution=64\n";
    return s;
  }();
  return spec;
}

int runRender(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(renderSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(renderSpec());
    return 0;
  }
  // Under mpirun (docs/mpi.md) rank 0 reports and writes; every process renders its share.
  Collective* const world = cli::world();
  const bool root = !world || world->root();
  bool quiet = args.has("--quiet") || !root;
  LoadedScene loaded = loadSceneWithOverrides(args, true);
  Scene& scene = loaded.scene;
  RenderOptions options;
  applyEstimatorOptions(args, options);
  options.memoryBudget = memoryBudget(args);
  options.gateCutoff = !args.has("--no-gate-cutoff");
  options.profile = args.has("--profile");
  const std::string pilot = args.get("--pilot").value_or("auto");
  if (pilot != "auto" && pilot != "on" && pilot != "off")
    throw UsageError("--pilot: '" + pilot + "' is not one of auto, on, off");
  // --out FILE.hdf5 / FILE.h5: the scan as an NLOS capture in place of the EXR.
  const bool capture = args.get("--out") && isCapturePath(*args.get("--out"));
  std::filesystem::path exr = capture ? std::filesystem::path(*args.get("--out")) : outputPath(args, "render");
  std::filesystem::path png = withExtension(exr, ".png");
  std::filesystem::path npy = withExtension(exr, ".npy");
  std::vector<std::filesystem::path> inputs;
  if (!args.positionals.empty()) inputs.push_back(args.positionals[0]);
  const std::optional<Scan> scan = scanOf(args, scene, inputs, std::move(loaded.capture));
  if (capture) checkScanCapture(scene, scan, exr);
  for (const auto& out : {exr, png, npy}) checkOutputPath(out, inputs);

  auto context = makeContext(args);
  auto wallStart = std::chrono::steady_clock::now();
  Renderer renderer(*context);
  DeviceScene deviceScene(*context, scene);
  RenderSetup setup = RenderSetup::of(scene);
  const std::vector<RenderView> allViews = scan ? scanViews(*scan, scene) : std::vector<RenderView>{};
  // Each process renders its share of the scan's views (each view's image is bits of its own,
  // whichever views it is rendered with); a render of one view is rank 0's alone: split by samples,
  // its pixels would sum their samples in another order.
  const Share share = shareOf(allViews.size(), world);
  const std::vector<RenderView> views(allViews.begin() + ptrdiff_t(share.begin), allViews.begin() + ptrdiff_t(share.end));
  if (scan) {
    // The pilot measures the first view.
    setup.camera = allViews.front().camera;
    deviceScene.placePointLights(allViews.front().lightPositions);
  }
  if (pilot != "off") {
    // The pilot's choice rests on timings: rank 0's holds for all.
    if (root) chooseNeeByPilot(renderer, deviceScene, setup, options, pilot == "auto");
    if (world) options.nee = NeeMode(int(broadcastDouble(*world, double(int(options.nee)))));
  }
  options.progress = makeProgress("render", quiet);
  RenderResult result;
  if (scan && !views.empty()) result = renderer.render(deviceScene, setup, views, options);
  else if (!scan && root) result = renderer.render(deviceScene, setup, options);
  if (world) {
    if (scan) result.mean = gatherStackedViews(*world, result.mean);
    sumStats(*world, result.stats);
  }
  if (!root) return finishWithValidationCheck(*context, result.stats.nonFinite == 0 ? 0 : 4);
  if (scan) result.mean = scanImage(result.mean, *scan, scene.camera.type);
  if (args.has("--explain")) std::cout << "plan (" << context->report().name << "):\n" << explainPlan(result.plan);

  if (capture) {
    // What tal keeps in scene_info: where the transients came from.
    const nlohmann::json info = {{"generator", "vktg render"},
                                 {"scene", args.positionals.empty() ? std::string("(built-in default)") : args.positionals[0]},
                                 {"scan", args.get("--scan").value_or("(the scene's nlos_capture_meter)")},
                                 {"defines", definesOf(args)},
                                 {"spp", scene.render.spp},
                                 {"seed", scene.render.seed},
                                 {"gate", scene.gate.describe()}};
    writeCaptureTal(exr, scanCapture(scene, *scan, result.mean, info.dump() + "\n"));
  } else {
    writeExr(exr, result.mean);
  }
  if (result.mean.layers.size() == 1)
    writePngRadiance(png, result.mean.width, result.mean.height, result.mean.layers[0].pixels);
  else
    writePngContactSheet(png, result.mean);
  if (args.has("--npy")) writeNpy(npy, result.mean);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();

  const RenderStats& st = result.stats;
  if (args.has("--profile")) {
    std::printf("GPU time per pass (%u batches of %u paths):\n", st.batches, st.batchSize);
    double total = 0;
    for (const auto& [name, ms] : result.passMilliseconds) total += ms;
    for (const auto& [name, ms] : result.passMilliseconds)
      std::printf("  %-22s %10.2f ms  %5.1f%%\n", name.c_str(), ms, total > 0 ? 100.0 * ms / total : 0.0);
    std::printf("  %-22s %10.2f ms\n", "total", total);
  }
  if (!quiet) {
    std::fprintf(stderr, "vktg: %s, %ux%u, %u spp, %s NEE on %s\n", scene.gate.describe().c_str(), result.mean.width,
                 result.mean.height, scene.render.spp, neeModeName(result.plan.nee), context->report().name.c_str());
    if (scan && world && world->size() > 1)
      std::fprintf(stderr, "vktg: %zu scan views (%u x %u) over %d processes\n", scan->views.size(), scan->columns, scan->rows,
                   world->size());
    else if (scan)
      std::fprintf(stderr, "vktg: %zu scan views (%u x %u) in one render\n", scan->views.size(), scan->columns, scan->rows);
    else if (world && world->size() > 1)
      std::fprintf(stderr, "vktg: one view: rendered by rank 0 alone (a view's samples are not split over processes)\n");
    std::fprintf(stderr, "vktg: %.3f s render (%.3f s total): %.3g paths/s, %.3g rays/s\n", st.seconds, wall,
                 double(st.paths) / st.seconds, double(st.extensionRays + st.shadowRays) / st.seconds);
    std::fprintf(stderr, "vktg: %llu paths ended by the gate cutoff, %llu by roulette, %llu at max depth; %llu non-finite\n",
                 (unsigned long long)st.endedByGate, (unsigned long long)st.endedByRoulette,
                 (unsigned long long)st.endedByDepth, (unsigned long long)st.nonFinite);
    std::fprintf(stderr, "vktg: wrote %s and %s%s%s\n", exr.string().c_str(), png.string().c_str(),
                 args.has("--npy") ? " and " : "", args.has("--npy") ? npy.string().c_str() : "");
  }
  return finishWithValidationCheck(*context, st.nonFinite == 0 ? 0 : 4);
}

}  // namespace vktg::cli
