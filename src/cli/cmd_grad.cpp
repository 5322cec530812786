// `vktg grad` and `vktg fd`: derivative images of a time-gated render with respect to scene
// parameters, and their finite-difference reference.
#include <cstdio>
#include <iostream>
#include <sstream>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/mpi_world.h"
#include "cli/scan_views.h"
#include "grad/gradient.h"
#include "vktg/image_io.h"

namespace vktg::cli {
namespace {

std::vector<OptionSpec> derivativeOptions() {
  std::vector<OptionSpec> options = sceneOverrideOptions();
  options.push_back({"--param", "NAMES", "comma-separated parameter names from the scene (a * matches any text)"});
  options.push_back({"--out", "FILE.exr", "output (default out/grad.exr or out/fd.exr); PNG previews go beside it"});
  options.push_back({"--npy", "", "also write FILE.npy, float32 of shape (H, W, parameters x layers)"});
  options.push_back(scanOption("the derivative images"));
  for (auto& o : deviceOptions()) options.push_back(o);
  return options;
}

// One EXR layer per (parameter, gate layer): "param" or "param.bin_...". With a scan, laid out as
// the scan's image (scanImage).
ImageSet derivativeLayers(const std::vector<std::string>& names, const std::vector<ImageSet>& images,
                          const std::optional<Scan>& scan, CameraType camera) {
  ImageSet out;
  out.width = images.at(0).width;
  out.height = images.at(0).height;
  for (size_t p = 0; p < names.size(); ++p)
    for (const ImageLayer& layer : images[p].layers)
      out.layers.push_back({layer.name.empty() ? names[p] : names[p] + "." + layer.name, layer.pixels});
  return scan ? scanImage(std::move(out), *scan, camera) : out;
}

// PNG previews in a diverging colormap, one per parameter (first layer; a contact sheet would
// need one shared scale), with the scale in the file name and printed.
void writePreviews(const std::filesystem::path& exr, const ImageSet& set, bool quiet) {
  for (const ImageLayer& layer : set.layers) {
    std::filesystem::path tmp = exr;
    tmp.replace_extension("");
    std::filesystem::path png = tmp.string() + "." + layer.name + ".png";
    float scale = writePngDiverging(png, set.width, set.height, layer.pixels);
    char scaled[64];
    std::snprintf(scaled, sizeof scaled, "%.3g", scale);
    if (!quiet) std::fprintf(stderr, "vktg: %s: red +%s, blue -%s\n", png.string().c_str(), scaled, scaled);
  }
}

}  // namespace

const CommandSpec& gradSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "grad";
    s.usage = "grad [SCENE] --param NAME[,NAME...] [options]";
    s.description =
        "Derivatives of the time-gated image with respect to scene parameters (forward mode through the\n"
        "wavefront passes). Writes one EXR layer per parameter (per bin for a transient stack) and a PNG\n"
        "per layer in a diverging colormap (red positive, blue negative, the scale printed).\n"
        "SCENE omitted: the built-in default scene (its parameters: short_box_x, tall_box_spin, light_emission,\n"
        "left_albedo). Terms (docs/theory.md section 3), each its own pass: interior, edge (visibility boundary: moving\n"
        "silhouettes and shadows; boundary segments from the camera and from the first hit) and\n"
        "path-length boundary (the gate's jumps). --explain says which run and why.";
    s.options = derivativeOptions();
    s.options.push_back({"--terms", "LIST", "terms to compute: interior,edge,pathlength (default: those the planner finds needed)"});
    s.options.push_back({"--split-terms", "", "also write each term's images (FILE.interior.exr, FILE.edge.exr, FILE.pathlength.exr; with --npy their .npy too)"});
    s.options.push_back({"--spp-boundary", "N", "samples per pixel of the path-length-boundary pass (default: --spp)"});
    s.options.push_back({"--spp-boundary-camera", "N",
                         "of its connections from the camera, splatted (default: --spp-boundary)"});
    s.options.push_back({"--spp-edge", "N", "edge samples per pixel, on average, of the edge pass (default: --spp)"});
    s.options.push_back({"--antithetic", "MODE", "auto | on | off: antithetic pairs (mirrored lengths of a gaussian gate; both jumps of a box or truncated gaussian in the path-length-boundary pass), auto: for near-delta gates (default)"});
    s.options.push_back({"--explain", "", "print the planner's choices and why"});
    s.examples = "  vktg grad scenes/occluder_shadow.json --param occluder_x,floor_albedo\n"
                 "  vktg grad scenes/confocal_plane.json --param '*' --spp 100000\n"
                 "  vktg grad experiments/confocal_scan/scene.json --scan experiments/confocal_scan/scan.json --param h27,h36\n";
    return s;
  }();
  return spec;
}

const CommandSpec& fdSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "fd";
    s.usage = "fd [SCENE] --param NAME --eps E [options]";
    s.description =
        "Central finite difference (I(θ+E) - I(θ-E)) / 2E of the render, both sides with the same random\n"
        "numbers: the reference `vktg grad` is validated against.";
    s.options = derivativeOptions();
    s.options.push_back({"--eps", "E", "the step (parameter units)"});
    s.examples = "  vktg fd scenes/occluder_shadow.json --param floor_albedo --eps 0.01\n";
    return s;
  }();
  return spec;
}

int runGrad(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(gradSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(gradSpec());
    return 0;
  }
  // Under mpirun (docs/mpi.md) each process differentiates its share of the scan's views; rank 0
  // gathers and writes.
  Collective* const world = cli::world();
  const bool root = !world || world->root();
  bool quiet = args.has("--quiet") || !root;
  LoadedScene loaded = loadSceneWithOverrides(args, true);
  Scene& scene = loaded.scene;
  std::vector<std::string> names = selectParameters(scene, args.get("--param").value_or(""));
  GradientOptions gradient;
  if (auto terms = args.get("--terms")) {
    gradient.interior = gradient.pathLength = gradient.edges = false;
    std::stringstream list(*terms);
    for (std::string term; std::getline(list, term, ',');) {
      if (term == termName(Term::Interior)) gradient.interior = true;
      else if (term == termName(Term::PathLength)) gradient.pathLength = true;
      else if (term == termName(Term::Edge)) gradient.edges = true;
      else throw UsageError("--terms: unknown term '" + term + "' (interior, edge, pathlength)");
    }
  }
  if (auto antithetic = args.get("--antithetic")) {
    if (*antithetic == "auto") gradient.antithetic = AntitheticMode::Auto;
    else if (*antithetic == "on") gradient.antithetic = AntitheticMode::On;
    else if (*antithetic == "off") gradient.antithetic = AntitheticMode::Off;
    else throw UsageError("--antithetic: '" + *antithetic + "' is not one of auto, on, off");
  }
  gradient.sppBoundary = args.count("--spp-boundary", 1, 1u << 24).value_or(0);
  gradient.sppBoundaryCamera = args.count("--spp-boundary-camera", 1, 1u << 24).value_or(0);
  gradient.sppEdge = args.count("--spp-edge", 1, 1u << 24).value_or(0);
  RenderOptions& options = gradient.render;
  applyEstimatorOptions(args, options);
  options.memoryBudget = memoryBudget(args);
  std::filesystem::path exr = outputPath(args, "grad");
  std::vector<std::filesystem::path> inputs(args.positionals.begin(), args.positionals.end());
  const std::optional<Scan> scan = scanOf(args, scene, inputs, std::move(loaded.capture));
  checkOutputPath(exr, inputs);
  for (const char* term : {".interior.exr", ".edge.exr", ".pathlength.exr", ".npy", ".interior.npy", ".edge.npy",
                           ".pathlength.npy"})
    checkOutputPath(withExtension(exr, term), inputs);
  auto context = makeContext(args);
  Renderer renderer(*context);
  options.progress = makeProgress("grad", quiet);
  const std::vector<RenderView> allViews = scan ? scanViews(*scan, scene) : std::vector<RenderView>{};
  // A view's derivative images are bits of their own whichever views they are rendered with; one
  // view is rank 0's alone (split by samples, its pixels would sum them in another order).
  const Share share = shareOf(allViews.size(), world);
  GradientResult result;
  if (scan && !share.empty())
    result = renderGradient(renderer, scene, names, gradient,
                            std::vector<RenderView>(allViews.begin() + ptrdiff_t(share.begin), allViews.begin() + ptrdiff_t(share.end)));
  else if (!scan && root)
    result = renderGradient(renderer, scene, names, gradient);
  if (world) {
    // Every term's images and the total, in one exchange: per parameter, the processes' views
    // stacked in order (a term that did not run: images without layers).
    std::vector<TermImages*> terms = {&result.total, &result.interior, &result.edges, &result.pathLength};
    std::vector<ImageSet> mine;
    for (TermImages* term : terms)
      for (size_t p = 0; p < names.size(); ++p) mine.push_back(p < term->derivatives.size() ? term->derivatives[p] : ImageSet{});
    if (scan) {
      const std::vector<ImageSet> all = gatherStackedViews(*world, mine);
      for (size_t k = 0; k < terms.size() && root; ++k) {
        terms[k]->derivatives.assign(all.begin() + ptrdiff_t(k * names.size()), all.begin() + ptrdiff_t((k + 1) * names.size()));
        if (terms[k]->derivatives.empty() || terms[k]->derivatives.front().layers.empty()) terms[k]->derivatives.clear();
      }
    }
    sumStats(*world, result.stats);
    if (!root) return finishWithValidationCheck(*context, result.stats.nonFinite == 0 ? 0 : 4);
  }
  if (args.has("--explain")) {
    std::cout << "plan (" << context->report().name << "):\n" << explainPlan(result.primal.plan);
    for (const std::string& reason : result.plan.reasons) std::cout << "  - " << reason << "\n";
    std::cout << "  - " << names.size() << " parameter(s) in blocks of " << kMaxDerivativeLanes << " lanes\n";
  }
  ImageSet layers = derivativeLayers(names, result.total.derivatives, scan, scene.camera.type);
  writeExr(exr, layers);
  if (args.has("--split-terms")) {
    for (const auto& [term, images] : {std::pair{Term::Interior, &result.interior}, std::pair{Term::Edge, &result.edges},
                                       std::pair{Term::PathLength, &result.pathLength}}) {
      if (images->derivatives.empty()) continue;
      std::filesystem::path split = withExtension(exr, std::string(".") + termName(term) + ".exr");
      const ImageSet termLayers = derivativeLayers(names, images->derivatives, scan, scene.camera.type);
      writeExr(split, termLayers);
      if (args.has("--npy")) writeNpy(withExtension(exr, std::string(".") + termName(term) + ".npy"), termLayers);
      if (!quiet) std::fprintf(stderr, "vktg: wrote %s\n", split.string().c_str());
    }
  }
  writePreviews(exr, layers, quiet);
  if (args.has("--npy")) writeNpy(withExtension(exr, ".npy"), layers);
  if (!quiet)
    std::fprintf(stderr, "vktg: %zu derivative layer(s) in %.3f s, %llu non-finite; wrote %s\n", layers.layers.size(),
                 result.stats.seconds, (unsigned long long)result.stats.nonFinite, exr.string().c_str());
  return finishWithValidationCheck(*context, result.stats.nonFinite == 0 ? 0 : 4);
}

int runFd(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(fdSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(fdSpec());
    return 0;
  }
  bool quiet = args.has("--quiet");
  LoadedScene loaded = loadSceneWithOverrides(args, true);
  Scene& scene = loaded.scene;
  auto param = args.get("--param");
  if (!param) throw UsageError("--param NAME is required");
  auto eps = args.number("--eps");
  if (!eps || !(*eps > 0)) throw UsageError("--eps E (a positive step) is required");
  RenderOptions options;
  applyEstimatorOptions(args, options);
  options.memoryBudget = memoryBudget(args);
  std::filesystem::path exr = outputPath(args, "fd");
  std::vector<std::filesystem::path> inputs(args.positionals.begin(), args.positionals.end());
  const std::optional<Scan> scan = scanOf(args, scene, inputs, std::move(loaded.capture));
  checkOutputPath(exr, inputs);
  auto context = makeContext(args);
  Renderer renderer(*context);
  options.progress = makeProgress("fd", quiet);
  FiniteDifferenceResult fd =
      finiteDifference(renderer, scene, *param, *eps, options, scan ? scanViews(*scan, scene) : std::vector<RenderView>{});
  ImageSet layers = derivativeLayers({*param}, {fd.derivative}, scan, scene.camera.type);
  writeExr(exr, layers);
  writePreviews(exr, layers, quiet);
  if (args.has("--npy")) writeNpy(withExtension(exr, ".npy"), layers);
  if (!quiet) std::fprintf(stderr, "vktg: finite difference in %.3f s; wrote %s\n", fd.stats.seconds, exr.string().c_str());
  return finishWithValidationCheck(*context, fd.stats.nonFinite == 0 ? 0 : 4);
}

}  // namespace vktg::cli
