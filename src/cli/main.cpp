// vktg: a differentiable time-gated renderer. Dispatches to the subcommands and turns every
// error into one `vktg: error: ...` line and a non-zero exit status. SIGINT and SIGTERM stop a
// run at the next safe point (host/interrupt.h) with nothing written; the exit status is then
// 128 + the signal number, as if the signal had ended the process. Under mpirun (docs/mpi.md) the
// processes join one world first; a process that fails on its own ends them all.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/mpi_world.h"
#include "render/interrupt.h"
#include "vk/vk_check.h"
#include "vk/vk_context.h"
#include "vktg/error.h"

namespace {

struct Subcommand {
  const char* name;
  int (*run)(const std::vector<std::string>&);
  const char* summary;
  bool splitsOverProcesses = false;  // under mpirun (docs/mpi.md)
};

const Subcommand kSubcommands[] = {
    {"render", vktg::cli::runRender, "render a time-gated image or transient stack", true},
    {"grad", vktg::cli::runGrad, "derivative images with respect to scene parameters", true},
    {"fd", vktg::cli::runFd, "finite-difference derivative (the reference for grad)"},
    {"optimize", vktg::cli::runOptimize, "recover scene parameters from time-of-flight images", true},
    {"bench", vktg::cli::runBench, "accuracy versus time and throughput benchmarks", true},  // scale alone (cmd_bench.cpp)
    {"inspect", vktg::cli::runInspect, "sizes, layers and statistics of an EXR output"},
    {"info", vktg::cli::runInfo, "Vulkan devices, features and limits"},
};

void printUsage(std::FILE* out) {
  std::fprintf(out, "usage: vktg COMMAND [options]   (vktg COMMAND --help for details)\n\ncommands:\n");
  for (const auto& c : kSubcommands) std::fprintf(out, "  %-8s %s\n", c.name, c.summary);
}

// One `vktg: error:` line for a failure. Under mpirun a failure all processes agreed on is printed
// by rank 0 alone (it names the rank that failed); any other names the rank it happened in.
void printError(const char* message, const char* suffix = "") {
  const vktg::Collective* world = vktg::cli::world();
  if (world && world->failureAgreed() && !world->root()) return;
  if (world && !world->failureAgreed() && world->size() > 1)
    std::fprintf(stderr, "vktg: error: rank %d of %d: %s%s\n", world->rank(), world->size(), message, suffix);
  else
    std::fprintf(stderr, "vktg: error: %s%s\n", message, suffix);
}

// Runs a subcommand; `failed` says whether it ended by an exception (its status then follows it).
int runSubcommand(const Subcommand& c, const std::vector<std::string>& args, bool& failed) {
  failed = true;
  try {
    const int status = c.run(args);
    failed = false;
    // A validation message at device destruction (an object never destroyed) fails the run as
    // any other validation message does (exit status 3).
    return status == 0 && vktg::validationFailedAtExit() ? 3 : status;
  } catch (const vktg::Interrupted& e) {
    printError(e.what());
    return 128 + e.signal();
  } catch (const vktg::cli::UsageError& e) {
    printError(e.what(), (std::string("\n(see `vktg ") + c.name + " --help`)").c_str());
    return 2;
  } catch (const vktg::Error& e) {
    printError(e.what());
    return 1;
  } catch (const vktg::VulkanError& e) {
    printError(e.what());
    return 1;
  } catch (const std::exception& e) {
    printError(e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    printUsage(stderr);
    return 2;
  }
  std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    printUsage(stdout);
    return 0;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  vktg::installInterruptHandlers();
  for (const auto& c : kSubcommands) {
    if (command != c.name) continue;
    try {
      vktg::cli::joinWorld();
    } catch (const vktg::Error& e) {
      std::fprintf(stderr, "vktg: error: %s\n", e.what());
      return 1;
    }
    // Commands that do not split their work would repeat it in every process, all writing the
    // same files.
    const vktg::Collective* joined = vktg::cli::world();
    if (joined && joined->size() > 1 && !c.splitsOverProcesses) {
      if (joined->root())
        std::fprintf(stderr, "vktg: error: `vktg %s` runs as one process; under mpirun only render, grad, optimize and "
                             "bench scale spread over processes (docs/mpi.md)\n", c.name);
      vktg::cli::leaveWorld();
      return 2;
    }
    bool failed = false;
    const int status = runSubcommand(c, args, failed);
    // A process that failed on its own may leave its peers waiting for it in an exchange: it
    // ends them all (mpirun reports the abort). One whose failure all agreed on ends normally.
    const vktg::Collective* world = vktg::cli::world();
    if (failed && world && world->size() > 1 && !world->failureAgreed()) vktg::cli::abortWorld(status);
    vktg::cli::leaveWorld();
    return status;
  }
  std::fprintf(stderr, "vktg: error: unknown command '%s'\n", command.c_str());
  printUsage(stderr);
  return 2;
}
