#include "cli/common.h"

#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <unistd.h>

#include "cli/mpi_world.h"
#include "scene/mitsuba_xml.h"
#include "scene/mitsuba_xml_document.h"
#include "vktg/error.h"

namespace vktg::cli {

std::vector<OptionSpec> deviceOptions() {
  return {{"--device", "D",
           "Vulkan device: index or name substring from `vktg info`, or gpu (default: $VKTG_DEVICE, else a GPU, else lavapipe)"},
          {"--mem", "MIB", "memory budget for film and wavefront state in MiB, the scene not counted (default 512 on a CPU device; on a GPU a quarter of its memory, 512 to 4096)"},
          {"--quiet", "", "no progress or summary on stderr"},
          {"--help", "", "show this help"}};
}

std::vector<OptionSpec> sceneOverrideOptions() {
  return {{"--gate", "SPEC", "gaussian:MU,SIGMA | box:A,B | tgauss:MU,SIGMA,A,B | steady | bins:START,WIDTH,COUNT (metres, or ns suffix)"},
          {"--spp", "N", "samples per pixel"},
          {"--seed", "N", "random seed (renders are reproducible from it)"},
          {"--max-depth", "N", "maximum path vertices after the camera"},
          {"--resolution", "WxH", "image size (perspective cameras)"},
          {"--nee", "MODE", "auto | standard | ellipsoidal | mis (default: the planner's choice)"},
          {"--ellipsoid-selection", "HOW", "auto | descend | enumerate: how ellipsoidal connections choose a triangle (default: the planner's choice)"},
          defineOption()};
}

OptionSpec defineOption() {
  return {"--define", "NAME=VALUE",
          "a Mitsuba XML scene's parameter $NAME (overrides its <default>; repeat for several)", "-D", true};
}

SceneDefines definesOf(const ParsedArgs& args) {
  SceneDefines defines;
  for (const std::string& item : args.all("--define")) {
    const size_t eq = item.find('=');
    const std::string name = item.substr(0, eq);
    if (eq == std::string::npos || !isValidDefineName(name))
      throw UsageError("-D: '" + item + "' must be NAME=VALUE, NAME of letters, digits and '_'");
    if (!defines.emplace(name, item.substr(eq + 1)).second) throw UsageError("-D: " + name + " is defined twice");
  }
  return defines;
}

std::unique_ptr<VulkanContext> makeContext(const ParsedArgs& args) {
  ContextOptions options = contextOptionsFromEnvironment();
  if (auto device = args.get("--device")) options.device = *device;
  // Under mpirun the processes of one machine take a GPU each, the local rank-th (round robin when
  // there are more processes than GPUs); without a GPU they share the default device.
  if (const Collective* w = world(); w && w->size() > 1 && (options.device.empty() || options.device == "gpu")) {
    std::vector<uint32_t> gpus;
    for (const DeviceReport& d : VulkanContext::listDevices())
      if (d.usable && d.type != "cpu") gpus.push_back(d.index);
    if (!gpus.empty()) options.device = std::to_string(gpus[size_t(localRank()) % gpus.size()]);
  }
  return std::make_unique<VulkanContext>(options);
}

int finishWithValidationCheck(VulkanContext& context, int status) {
  auto messages = context.takeValidationMessages();
  for (const auto& m : messages) std::cerr << "vktg: validation: " << m << "\n";
  return messages.empty() ? status : 3;
}

NeeMode parseNeeMode(const std::string& text) {
  if (text == "auto") return NeeMode::Auto;
  if (text == "standard") return NeeMode::Standard;
  if (text == "ellipsoidal") return NeeMode::Ellipsoidal;
  if (text == "mis") return NeeMode::Mis;
  throw UsageError("--nee: '" + text + "' is not one of auto, standard, ellipsoidal, mis");
}

void applyEstimatorOptions(const ParsedArgs& args, RenderOptions& options) {
  if (auto nee = args.get("--nee")) options.nee = parseNeeMode(*nee);
  if (auto how = args.get("--ellipsoid-selection")) {
    if (*how == "auto") options.ellipsoidSelection = EllipsoidSelection::Auto;
    else if (*how == "descend") options.ellipsoidSelection = EllipsoidSelection::Descend;
    else if (*how == "enumerate") options.ellipsoidSelection = EllipsoidSelection::Enumerate;
    else throw UsageError("--ellipsoid-selection: '" + *how + "' is not one of auto, descend, enumerate");
  }
}

uint64_t memoryBudget(const ParsedArgs& args) {
  auto mib = args.count("--mem", 16, 1u << 20);
  return uint64_t(mib.value_or(0)) << 20;  // 0: the device's default (defaultMemoryBudget)
}

LoadedScene loadSceneWithOverrides(const ParsedArgs& args, bool allowDefault) {
  LoadedScene loaded;
  Scene& scene = loaded.scene;
  const SceneDefines defines = definesOf(args);
  if (args.positionals.empty()) {
    if (!allowDefault) throw UsageError("a scene file is required");
    if (!defines.empty()) throw UsageError("-D: the built-in default scene has no parameters (name a Mitsuba XML scene)");
    scene = defaultScene();
  } else if (isMitsubaXmlPath(args.positionals[0])) {
    MitsubaScene xml = loadMitsubaXml(args.positionals[0], defines);
    scene = std::move(xml.scene);
    loaded.capture = std::move(xml.capture);
  } else {
    scene = loadScene(args.positionals[0], defines);
  }
  if (auto gate = args.get("--gate")) scene.gate = parseGateSpec(*gate, "--gate");
  if (auto spp = args.count("--spp", 1, 1u << 24)) scene.render.spp = *spp;
  if (auto seed = args.count("--seed", 0, 0xffffffffu)) scene.render.seed = *seed;
  if (auto depth = args.count("--max-depth", 1, 1024)) scene.render.maxDepth = *depth;
  if (auto res = args.get("--resolution")) {
    unsigned w = 0, h = 0;
    char extra = 0;
    if (std::sscanf(res->c_str(), "%ux%u%c", &w, &h, &extra) != 2 || w == 0 || h == 0 || w > 16384 || h > 16384)
      throw UsageError("--resolution: '" + *res + "' must be WxH with 1 <= W, H <= 16384");
    if (scene.camera.type == CameraType::PointSensor)
      throw UsageError("--resolution: the scene's camera is a point sensor (one pixel)");
    scene.camera.width = w;
    scene.camera.height = h;
  }
  return loaded;
}

std::function<void(double)> makeProgress(const std::string& label, bool quiet) {
  if (quiet) return {};
  bool tty = isatty(STDERR_FILENO);
  auto lastQuarter = std::make_shared<int>(-1);
  return [label, tty, lastQuarter](double fraction) {
    if (tty) {
      int filled = int(fraction * 30);
      std::fprintf(stderr, "\r%s [%-30s] %3d%%", label.c_str(), std::string(size_t(filled), '#').c_str(),
                   int(fraction * 100));
      if (fraction >= 1.0) std::fprintf(stderr, "\n");
      std::fflush(stderr);
    } else if (int quarter = int(fraction * 4); quarter > *lastQuarter) {
      *lastQuarter = quarter;
      std::fprintf(stderr, "%s: %d%%\n", label.c_str(), quarter * 25);
    }
  };
}

std::filesystem::path withExtension(const std::filesystem::path& path, const std::string& extension) {
  std::filesystem::path out = path;
  out.replace_extension(extension);
  return out;
}

std::filesystem::path outputPath(const ParsedArgs& args, const std::string& stem) {
  if (auto out = args.get("--out")) {
    std::filesystem::path p(*out);
    if (p.extension() != ".exr") throw UsageError("--out: '" + *out + "' must end in .exr");
    return p;
  }
  std::filesystem::create_directories("out");
  return std::filesystem::path("out") / (stem + ".exr");
}

}  // namespace vktg::cli
