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

}  // namespace vktg::cli
