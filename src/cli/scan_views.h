// What the commands that take --scan share: the option and the scan it names (the views and the
// image of a scan: render/scan_views.h).
#pragma once
#include <optional>
#include <vector>

#include "cli/args.h"
#include "render/scan_views.h"
#include "scene/scan.h"

namespace vktg::cli {

// The --scan option's help, the same for every command that takes it.
OptionSpec scanOption(const char* what);

// The scan named by --scan (its file joins `inputs`, which outputs must not overwrite), else the
// scene file's own capture, if it has one.
std::optional<Scan> scanOf(const ParsedArgs& args, const Scene& scene, std::vector<std::filesystem::path>& inputs,
                           std::optional<Scan> capture);

}  // namespace vktg::cli
