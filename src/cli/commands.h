// The subcommands of the `vktg` executable.
#pragma once
#include <string>
#include <vector>

#include "cli/args.h"

namespace vktg::cli {

int runRender(const std::vector<std::string>& args);
int runInfo(const std::vector<std::string>& args);
int runBench(const std::vector<std::string>& args);
int runInspect(const std::vector<std::string>& args);
int runGrad(const std::vector<std::string>& args);
int runFd(const std::vector<std::string>& args);
int runOptimize(const std::vector<std::string>& args);

// Each command's option table (its parser's input), and all of them (the fuzz target's list).
const CommandSpec& renderSpec();
const CommandSpec& gradSpec();
const CommandSpec& fdSpec();
const CommandSpec& optimizeSpec();
const CommandSpec& benchSpec();
const CommandSpec& inspectSpec();
const CommandSpec& infoSpec();
inline std::vector<const CommandSpec*> commandSpecs() {
  return {&renderSpec(), &gradSpec(), &fdSpec(), &optimizeSpec(), &benchSpec(), &inspectSpec(), &infoSpec()};
}

}  // namespace vktg::cli
