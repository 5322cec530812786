// `vktg bench render`: error-versus-time curves of the forward estimators, throughput, time per
// pass, memory; writes a run directory (CSV, plot, markdown table).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <iostream>

#include "cli/commands.h"
#include "cli/common.h"
#include "bench/bench_bvh.h"
#include "bench/bench_nee.h"
#include "bench/bench_optimize.h"
#include "bench/bench_pilot.h"
#include "bench/bench_trace.h"
#include "bench/bench_grad.h"
#include "bench/bench_render.h"
#include "bench/bench_scale.h"
#include "cli/mpi_world.h"

namespace vktg::cli {

const CommandSpec& benchSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "bench";
    s.usage = "bench render|grad|optimize|nee|pilot|trace|bvh|scale [options]";
    s.description =
        "Measures accuracy versus time: relMSE against an exact (confocal plane) or cached high-sample\n"
        "(Cornell box) reference for gaussian gates with sigma/mu in {1e-1, 1e-2, 1e-3} and a box gate,\n"
        "with standard and ellipsoidal NEE; paths/s, rays/s, time per pass, memory, and what the gate\n"
        "cutoff saves. `bench grad`: relMSE versus time of d M / d h on the confocal plane against its exact\n"
        "value (standard, ellipsoidal and antithetic estimators), of the path-length-boundary term with and\n"
        "without antithetic pairs, of the edge term against its budget, and the time of a gradient relative\n"
        "to a render. `bench optimize`: the cost of a loss gradient with respect to every height of an n x n\n"
        "heightfield (each term alone and all three) relative to a render, as n grows, against forward-mode\n"
        "lanes, and of a whole iteration of `vktg optimize`. `bench nee`: the cost per path of standard NEE and of\n"
        "ellipsoidal NEE (triangles chosen by BVH descent or by enumeration) in the default room with an n x n\n"
        "heightfield on its floor, as n grows; every point renders until a time budget. `bench pilot`: how well the\n"
        "pilot that picks NEE for `vktg render` predicts each estimator's time and relMSE (measured from --runs seeds\n"
        "of the full render), and what its choice and the gate-width rule's cost against the best. Writes bench.csv and\n"
        "table.md (and plot.png, except nee and trace) into the output directory. `bench trace [SCENE]`: rays per\n"
        "second of the BVH traversal, closest and any hit, primary and incoherent rays, on SCENE or on the default\n"
        "room and rooms with heightfields of --sizes, beside Embree on the host's cores when built with it.\n"
        "`bench bvh`: the median time to build the BVH of 10^4, 10^5 and 10^6 random triangles, and the silhouette-edge\n"
        "list of heightfields of as many vertices (CPU only; prints tables). `bench scale [EXPERIMENT]`, run under\n"
        "`mpirun -np N` for each N (or alone for 1): an optimisation's time per iteration and its all-reduce's share,\n"
        "one row of scale.csv per N, and table.md with a model of strong and weak scaling to 8 GPUs and 64 nodes\n"
        "(default experiment: experiments/confocal_scan/coarse_bins.experiment.json).";
    s.options = {{"--out", "DIR", "run directory (default runs/bench-render or runs/bench-grad)"},
                 {"--runs", "N", "repetitions per point; medians are reported (default 3)"},
                 {"--steps", "N", "spp doublings per curve (default 5)"},
                 {"--scale", "X", "multiplies every sample count (default 1; 0.25 for a quick look)"},
                 {"--point-seconds", "S", "render and grad: a curve's first point takes at least S seconds (its sample count doubles until it does, so a fast device is not timed on launch overhead; default 0.05, 0 keeps the counts)"},
                 {"--sizes", "N,N,...",
                  "optimize, nee, trace: heightfield vertices per side (default 11,100,1000; nee 17,257,725; trace 257,725)"},
                 {"--no-path-length", "", "optimize: leave out the path-length-boundary term"},
                 {"--profile", "", "optimize: device time per pass of the render and of every gradient variant (last run)"},
                 {"--positions", "", "optimize: every vertex's x, y and z as parameters (3 n^2: free-form geometry) instead of its height"},
                 {"--interior-passes", "M",
                  "optimize: also time an iteration whose render takes 1/M of the samples and whose interior term runs in M "
                  "chained passes (default 4; 1 leaves it out; M must divide the samples per pixel)"},
                 {"--no-embree", "", "trace: vktg only, even when built with Embree"},
                 {"--iterations", "N", "scale: iterations timed after the first (default 4)"},
                 defineOption()};
    for (auto& o : deviceOptions()) s.options.push_back(o);
    s.examples = "  vktg bench render --out runs/bench-render\n  vktg bench render --scale 0.25 --runs 1 --steps 3\n";
    return s;
  }();
  return spec;
}

// "11,100,1000": heightfield sizes of `bench optimize`, each in [2, 4096].
std::vector<uint32_t> parseSizes(const std::string& text) {
  std::vector<uint32_t> sizes;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    char* end = nullptr;
    const unsigned long n = std::strtoul(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || n < 2 || n > 4096)
      throw UsageError("--sizes: '" + item + "' is not a size in [2, 4096] (expected e.g. 11,100,1000)");
    sizes.push_back(uint32_t(n));
  }
  if (sizes.empty()) throw UsageError("--sizes: no size given");
  return sizes;
}

// `vktg bench scale` under mpirun: every process runs the optimisation, rank 0 reports.
int runBenchScale(const ParsedArgs& args, const std::vector<std::string>& argv) {
  if (args.positionals.size() > 2) throw UsageError("`vktg bench scale` takes one experiment file");
  Collective* const collective = world();
  const bool root = !collective || collective->root();
  BenchScaleOptions bench;
  bench.experiment = args.positionals.size() > 1
                         ? std::filesystem::path(args.positionals[1])
                         : std::filesystem::path("experiments") / "confocal_scan" / "coarse_bins.experiment.json";
  bench.outDir = args.get("--out").value_or("runs/bench-scale");
  bench.iterations = args.count("--iterations", 1, 1000).value_or(bench.iterations);
  bench.memoryBudget = memoryBudget(args);
  bench.collective = collective;
  if (root) std::filesystem::create_directories(bench.outDir);
  auto context = makeContext(args);
  const BenchScaleRow row = benchScale(*context, bench);
  if (root) {
    std::string command = collective ? "mpirun -np " + std::to_string(collective->size()) + " vktg bench" : "vktg bench";
    for (const auto& a : argv) command += " " + a;
    writeBenchScaleReport(row, bench, command);
    if (!args.has("--quiet")) std::fprintf(stderr, "bench: wrote %s/{scale.csv,table.md}\n", bench.outDir.string().c_str());
  }
  return finishWithValidationCheck(*context, 0);
}

int runBench(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(benchSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(benchSpec());
    return 0;
  }
  const std::string which = args.positionals.empty() ? "" : args.positionals[0];
  const std::vector<std::string> benchmarks = {"render", "grad", "optimize", "nee", "pilot", "trace", "bvh", "scale"};
  if (std::find(benchmarks.begin(), benchmarks.end(), which) == benchmarks.end())
    throw UsageError("which benchmark? `vktg bench render`, `grad`, `optimize`, `nee`, `pilot`, `trace`, `bvh` or `scale`");
  if (which == "scale") return runBenchScale(args, argv);
  if (world() && world()->size() > 1)
    throw UsageError("`vktg bench " + which + "` runs as one process; under mpirun only `vktg bench scale` (docs/mpi.md)");
  if (which != "trace" && args.positionals.size() > 1)
    throw UsageError("`vktg bench " + which + "` takes no scene file");
  if (which != "trace" && args.has("--define")) throw UsageError("-D: `vktg bench " + which + "` takes no scene file");
  if (which == "bvh") {
    const uint32_t runs = args.count("--runs", 1, 100).value_or(3);
    std::printf("| triangles | BVH build (median of %u) | nodes |\n| ---: | ---: | ---: |\n", runs);
    for (const BvhBenchRow& row : benchBvhBuild(runs))
      std::printf("| %u | %.3f s | %zu |\n", row.triangles, row.medianSeconds, row.nodes);
    std::printf("\n| heightfield vertices | triangles | silhouette-edge list (median of %u) | edges |\n| ---: | ---: | ---: | ---: |\n",
                runs);
    for (const EdgeListBenchRow& row : benchEdgeList(runs))
      std::printf("| %u | %zu | %.3f s | %zu |\n", row.vertices, row.triangles, row.medianSeconds, row.edges);
    return 0;
  }
  std::string command = "vktg bench";
  for (const auto& a : argv) command += " " + a;
  bool quiet = args.has("--quiet");
  auto log = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "bench: %s\n", line.c_str());
  };
  BenchOptions options;
  options.outDir = args.get("--out").value_or("runs/bench-" + which);
  options.runs = args.count("--runs", 1, 100).value_or(3);
  options.ladderSteps = args.count("--steps", 0, 12).value_or(5);
  if (auto scale = args.number("--scale")) {
    if (!(*scale > 0 && *scale <= 64)) throw UsageError("--scale must be in (0, 64]");
    options.scale = *scale;
  }
  if (auto seconds = args.number("--point-seconds")) {
    if (!(*seconds >= 0 && *seconds <= 600)) throw UsageError("--point-seconds must be in [0, 600]");
    options.pointSeconds = *seconds;
  }
  options.memoryBudget = memoryBudget(args);
  options.log = log;
  auto context = makeContext(args);
  if (which == "optimize") {
    BenchOptimizeOptions bench;
    static_cast<BenchOptions&>(bench) = options;
    if (auto sizes = args.get("--sizes")) bench.sizes = parseSizes(*sizes);
    bench.pathLength = !args.has("--no-path-length");
    bench.positions = args.has("--positions");
    bench.profile = args.has("--profile");
    bench.interiorPasses = args.count("--interior-passes", 1, 64).value_or(bench.interiorPasses);
    benchOptimize(*context, bench, [&](const BenchOptimizeReport& report) {
      writeBenchOptimizeReport(report, bench, command);  // after every size: an interrupted run keeps its rows
    });
    log("wrote " + options.outDir.string() + "/{bench.csv,plot.png,table.md}");
    return finishWithValidationCheck(*context, 0);
  }
  if (which == "trace") {
    BenchTraceOptions bench;
    static_cast<BenchOptions&>(bench) = options;
    if (args.positionals.size() > 1) bench.scene = args.positionals[1];
    bench.defines = definesOf(args);
    if (auto sizes = args.get("--sizes")) bench.sizes = parseSizes(*sizes);
    bench.embree = !args.has("--no-embree");
    writeBenchTraceReport(benchTrace(*context, bench), bench, command);
    log("wrote " + options.outDir.string() + "/{bench.csv,table.md}");
    return finishWithValidationCheck(*context, 0);
  }
  if (which == "nee") {
    BenchNeeOptions bench;
    static_cast<BenchOptions&>(bench) = options;
    if (auto sizes = args.get("--sizes")) bench.sizes = parseSizes(*sizes);
    writeBenchNeeReport(benchNee(*context, bench), bench, command);
    log("wrote " + options.outDir.string() + "/{bench.csv,table.md}");
    return finishWithValidationCheck(*context, 0);
  }
  if (which == "pilot") {
    writeBenchPilotReport(benchPilot(*context, options), options, command);
    log("wrote " + options.outDir.string() + "/{bench.csv,table.md}");
    return finishWithValidationCheck(*context, 0);
  }
  if (which == "grad")
    writeBenchGradReport(benchGrad(*context, options), options, command);
  else
    writeBenchRenderReport(benchRender(*context, options), options, command);
  log("wrote " + options.outDir.string() + "/{bench.csv,plot.png,table.md}");
  return finishWithValidationCheck(*context, 0);
}

}  // namespace vktg::cli
