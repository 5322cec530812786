// `vktg optimize`: recovers scene parameters from time-of-flight images by gradient descent
// (src/host/optimize.h; the experiment format and run directory: docs/optimize.md).
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/mpi_world.h"
#include "render/interrupt.h"
#include "optimize/optimize.h"

namespace vktg::cli {

const CommandSpec& optimizeSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "optimize";
    s.usage = "optimize EXPERIMENT.json --out RUN_DIR [options]   |   optimize --resume RUN_DIR [options]";
    s.description =
        "Inverse time-gated rendering: recovers the parameters an experiment file names from its target images\n"
        "(time-gated images, transient stacks, scans from several views) by gradient descent. Each iteration\n"
        "renders every target, forms the loss, and takes its gradient with respect to every parameter by adjoint\n"
        "renders of the derivative terms (cost independent of the number of parameters). RUN_DIR receives the\n"
        "log (log.csv), checkpoints, plots, image strips, the optimised parameters and scene. Ctrl-C writes a\n"
        "checkpoint and stops; --resume continues exactly where the run stopped.";
    s.options = {{"--out", "RUN_DIR", "run directory (must not exist, unless --force)"},
                 {"--resume", "RUN_DIR", "continue the run in RUN_DIR from its checkpoint"},
                 {"--force", "", "replace RUN_DIR if it holds an earlier run"},
                 {"--iterations", "N", "stop after N iterations in all (overrides stop.iterations)"},
                 {"--explain", "", "print the render and gradient plans of the first iteration"},
                 defineOption()};
    for (auto& o : deviceOptions()) s.options.push_back(o);
    s.examples =
        "  vktg optimize experiments/heightfield/experiment.json --out runs/hf\n"
        "  vktg optimize --resume runs/hf\n"
        "  vktg optimize --resume runs/hf --iterations 400\n";
    return s;
  }();
  return spec;
}

int runOptimize(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(optimizeSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(optimizeSpec());
    return 0;
  }
  OptimizeOptions options;
  options.resume = args.has("--resume");
  if (options.resume) {
    if (!args.positionals.empty()) throw UsageError("--resume takes the run directory; the experiment is the run's own");
    if (args.has("--out") || args.has("--force")) throw UsageError("--resume continues a run: no --out or --force");
    options.runDirectory = *args.get("--resume");
    if (args.has("--define")) throw UsageError("--resume continues a run with its own defines: no -D");
  } else {
    if (args.positionals.empty()) throw UsageError("an experiment file is required (or --resume RUN_DIR)");
    if (!args.has("--out")) throw UsageError("--out RUN_DIR is required");
    options.experiment = args.positionals[0];
    options.runDirectory = *args.get("--out");
  }
  options.force = args.has("--force");
  options.defines = definesOf(args);
  options.memoryBudget = memoryBudget(args);
  if (auto n = args.count("--iterations", 1, 1u << 30)) options.iterations = *n;
  options.explain = args.has("--explain");
  // Under mpirun (docs/mpi.md) the processes share the targets; rank 0 reports and writes.
  options.collective = world();
  const bool root = !options.collective || options.collective->root();
  const bool quiet = args.has("--quiet") || !root;
  options.progress = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "vktg: %s\n", line.c_str());
  };
  auto context = makeContext(args);
  try {
    OptimizeSummary summary = optimize(*context, options);
    if (!quiet) {
      std::fprintf(stderr, "vktg: stopped after %llu iterations (%s), %.1f s; loss %.4e", (unsigned long long)summary.iterations,
                   summary.stopReason.c_str(), summary.seconds, summary.loss);
      if (summary.parameterError) std::fprintf(stderr, ", parameter error %.4e", *summary.parameterError);
      std::fprintf(stderr, "\nvktg: results in %s\n", options.runDirectory.string().c_str());
    }
  } catch (const Interrupted& e) {
    if (!root) throw;
    std::fprintf(stderr, "vktg: %s: checkpoint written; continue with `vktg optimize --resume %s`\n", e.what(),
                 options.runDirectory.string().c_str());
    // Interrupted where its peers may be waiting for it (mid-render): they are ended (main.cpp).
    if (options.collective && !options.collective->failureAgreed()) throw;
    return 128 + e.signal();
  }
  return finishWithValidationCheck(*context, 0);
}

}  // namespace vktg::cli
