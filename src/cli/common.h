// Pieces every subcommand shares: device options, scene loading with command-line overrides,
// progress display, and where outputs go.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "cli/args.h"
#include "render/renderer.h"
#include "scene/scan.h"
#include "vk/vk_context.h"
#include "vktg/scene.h"

namespace vktg::cli {

// Options understood by every command that renders.
std::vector<OptionSpec> deviceOptions();
std::vector<OptionSpec> sceneOverrideOptions();

// A context for --device, with validation when VKTG_VALIDATION=1.
std::unique_ptr<VulkanContext> makeContext(const ParsedArgs& args);
// Fails (exit status 3) if the validation layer reported anything during the run.
int finishWithValidationCheck(VulkanContext& context, int status);

// -D NAME=VALUE / --define NAME=VALUE: a Mitsuba XML scene's $NAME parameter (repeatable).
OptionSpec defineOption();
// The values of every -D, by name; a malformed or repeated name is a UsageError.
SceneDefines definesOf(const ParsedArgs& args);

// A scene as a command loads it: a Mitsuba XML capture (nlos_capture_meter) also brings the scan of
// its wall points, which the commands render when no --scan is given.
struct LoadedScene {
  Scene scene;
  std::optional<Scan> capture;
};

// The scene named by the first positional argument (or the built-in default), with -D defines,
// --gate, --spp, --seed, --max-depth, --resolution applied.
LoadedScene loadSceneWithOverrides(const ParsedArgs& args, bool allowDefault);
NeeMode parseNeeMode(const std::string& text);
// --nee and --ellipsoid-selection (sceneOverrideOptions) into `options`.
void applyEstimatorOptions(const ParsedArgs& args, RenderOptions& options);
uint64_t memoryBudget(const ParsedArgs& args);

// Progress on stderr: a bar on a terminal, a few plain lines otherwise, nothing with --quiet.
std::function<void(double)> makeProgress(const std::string& label, bool quiet);

// The output path: --out, else out/<stem>.exr (creating out/ when it is the default).
std::filesystem::path outputPath(const ParsedArgs& args, const std::string& stem);
std::filesystem::path withExtension(const std::filesystem::path& path, const std::string& extension);

}  // namespace vktg::cli
