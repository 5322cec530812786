// `vktg bench render`: error-versus-time curves of the forward estimators, throughput, time per
// pass, memory; writes a run directory (CSV, plot, markdown table).
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "cli/common.h"
#include "host/bench_bvh.h"
#include "host/bench_grad.h"
#include "host/bench_render.h"

namespace vktg::cli {

const CommandSpec& benchSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "bench";
    s.usage = "bench render|grad|bvh [options]";
    s.description =
        "Measures accuracy versus time: relMSE against an exact (confocal plane) or cached high-sample\n"
        "(Cornell box) reference for gaussian gates with sigma/mu in {1e-1, 1e-2, 1e-3} and a box gate,\n"
        "with standard and ellipsoidal NEE; paths/s, rays/s, time per pass, memory, and what the gate\n"
        "cutoff saves. `bench grad`: relMSE versus time of d M / d h on the confocal plane against its exact\n"
        "value (standard, ellipsoidal and antithetic estimators), of the path-length-boundary term with and\n"
        "without antithetic pairs, of the edge term against its budget, and the time of a gradient relative\n"
        "to a render. Writes bench.csv, plot.png and table.md into the output directory. `bench bvh`: the\n"
        "median time to build the BVH of 10^4, 10^5 and 10^6 random triangles (CPU only; prints a table).";
    s.options = {{"--out", "DIR", "run directory (default runs/bench-render or runs/bench-grad)"},
                 {"--runs", "N", "repetitions per point; medians are reported (default 3)"},
                 {"--steps", "N", "spp doublings per curve (default 5)"},
                 {"--scale", "X", "multiplies every sample count (default 1; 0.25 for a quick look)"}};
    for (auto& o : deviceOptions()) s.options.push_back(o);
    s.examples = "  vktg bench render --out runs/bench-render\n  vktg bench render --scale 0.25 --runs 1 --steps 3\n";
    return s;
  }();
  return spec;
}

int runBench(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(benchSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(benchSpec());
    return 0;
  }
  const std::string which = args.positionals.empty() ? "" : args.positionals[0];
  if (which != "render" && which != "grad" && which != "bvh")
    throw UsageError("which benchmark? `vktg bench render`, `vktg bench grad` or `vktg bench bvh`");
  if (which == "bvh") {
    std::printf("| triangles | BVH build (median of %u) | nodes |\n| ---: | ---: | ---: |\n",
                args.count("--runs", 1, 100).value_or(3));
    for (const BvhBenchRow& row : benchBvhBuild(args.count("--runs", 1, 100).value_or(3)))
      std::printf("| %u | %.3f s | %zu |\n", row.triangles, row.medianSeconds, row.nodes);
    return 0;
  }
  std::string command = "vktg bench";
  for (const auto& a : argv) command += " " + a;
  bool quiet = args.has("--quiet");
  auto log = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "bench: %s\n", line.c_str());
  };
  BenchOptions options;
  options.outDir = args.get("--out").value_or(args.positionals[0] == "grad" ? "runs/bench-grad" : "runs/bench-render");
  options.runs = args.count("--runs", 1, 100).value_or(3);
  options.ladderSteps = args.count("--steps", 0, 12).value_or(5);
  if (auto scale = args.number("--scale")) {
    if (!(*scale > 0 && *scale <= 64)) throw UsageError("--scale must be in (0, 64]");
    options.scale = *scale;
  }
  options.memoryBudget = memoryBudget(args);
  options.log = log;
  auto context = makeContext(args);
  if (args.positionals[0] == "grad")
    writeBenchGradReport(benchGrad(*context, options), options, command);
  else
    writeBenchRenderReport(benchRender(*context, options), options, command);
  log("wrote " + options.outDir.string() + "/{bench.csv,plot.png,table.md}");
  return finishWithValidationCheck(*context, 0);
}

}  // namespace vktg::cli
