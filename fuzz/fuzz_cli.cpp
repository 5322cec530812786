// Fuzz target: the command-line parser. The input is a NUL-separated argument list whose first
// entry names the command; the arguments go through that command's option table (parseArgs) and
// the interpreters every rendering command applies before it opens a device: scene overrides on
// the built-in scene (--gate, --spp, --seed, --max-depth, --resolution), --nee, --mem, --eps,
// the sample counts and --param. Positionals (file names) are dropped: files are other targets'.
// Errors must be a UsageError or a vktg::Error.
// vktg-fuzz-seeds: fuzz/seeds/cli/*
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/common.h"
#include "fuzz_support.h"
#include "vktg/parameters.h"

namespace {

std::vector<std::string> splitArguments(const uint8_t* data, size_t size) {
  std::vector<std::string> args(1);
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == 0) args.emplace_back();
    else args.back().push_back(char(data[i]));
  }
  return args;
}

const vktg::cli::CommandSpec* findSpec(const std::string& name) {
  for (const vktg::cli::CommandSpec* spec : vktg::cli::commandSpecs())
    if (spec->name == name) return spec;
  return nullptr;
}

void interpret(const vktg::cli::CommandSpec& spec, std::vector<std::string> argv) {
  using namespace vktg::cli;
  ParsedArgs args = parseArgs(spec, argv);
  args.positionals.clear();
  vktg::Scene scene = loadSceneWithOverrides(args, true);
  if (auto nee = args.get("--nee")) parseNeeMode(*nee);
  if (spec.name != "inspect" && spec.name != "info") memoryBudget(args);
  args.number("--eps");
  args.count("--spp-edge", 1, 1u << 24);
  args.count("--spp-boundary", 1, 1u << 24);
  args.count("--iterations", 1, 1u << 30);
  if (auto names = args.get("--param")) vktg::selectParameters(scene, *names);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args = splitArguments(data, size);
  const vktg::cli::CommandSpec* spec = findSpec(args[0]);
  if (!spec) return 0;
  args.erase(args.begin());
  vktg::fuzz::expectOnlyVktgErrors([&] {
    try {
      interpret(*spec, args);
    } catch (const vktg::cli::UsageError&) {
    }
  });
  return 0;
}
