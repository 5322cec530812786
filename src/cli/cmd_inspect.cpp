// `vktg inspect FILE.exr`: what an output holds — size, layers, and per-layer statistics
// (non-finite pixels are counted: a vktg output never has any).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>

#include "cli/commands.h"
#include "vktg/image_io.h"

namespace vktg::cli {

const CommandSpec& inspectSpec() {
  static const CommandSpec spec = [] {
    CommandSpec s;
    s.name = "inspect";
    s.usage = "inspect FILE.exr [FILE.exr...]";
    s.description = "Prints an EXR's size and, per layer, its name, min, mean, max and non-finite pixel count.";
    s.options = {{"--help", "", "show this help"}};
    s.maxPositionals = 64;
    s.examples = "  vktg inspect out/render.exr\n  vktg inspect out/grad.exr out/fd.exr\n";
    return s;
  }();
  return spec;
}

int runInspect(const std::vector<std::string>& argv) {
  ParsedArgs args = parseArgs(inspectSpec(), argv);
  if (args.has("--help")) {
    std::cout << helpText(inspectSpec());
    return 0;
  }
  if (args.positionals.empty()) throw UsageError("an EXR file is required");
  size_t nonFiniteTotal = 0;
  for (const std::string& file : args.positionals) {
    ImageSet images = readExr(file);
    std::printf("%s: %u x %u, %zu layer(s)\n", file.c_str(), images.width, images.height, images.layers.size());
    for (const ImageLayer& layer : images.layers) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
      size_t finite = 0, nonFinite = 0;
      for (float v : layer.pixels) {
        if (!std::isfinite(v)) {
          nonFinite++;
          continue;
        }
        lo = std::min(lo, double(v));
        hi = std::max(hi, double(v));
        sum += v;
        finite++;
      }
      nonFiniteTotal += nonFinite;
      std::printf("  %-28s min %-12.5g mean %-12.5g max %-12.5g non-finite %zu\n",
                  layer.name.empty() ? "(Y)" : layer.name.c_str(), finite ? lo : 0.0,
                  finite ? sum / double(finite) : 0.0, finite ? hi : 0.0, nonFinite);
    }
  }
  return nonFiniteTotal == 0 ? 0 : 4;
}

}  // namespace vktg::cli
