#include "bench/bench_common.h"

#include "plot_bench_script.h"
#include "vktg/image_io.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace vktg {

Gate gaussianGate(double mu, double sigma) {
  Gate g;
  g.type = GateType::Gaussian;
  g.mu = mu;
  g.sigma = sigma;
  return g;
}

Gate boxGate(double a, double b) {
  Gate g;
  g.type = GateType::Box;
  g.a = a;
  g.b = b;
  return g;
}

uint32_t firstLadderSpp(double baseSpp, const BenchOptions& options, const std::function<double(uint32_t spp)>& secondsAt) {
  // The ladder doubles from here options.ladderSteps times and must stay within the 2^30 spp a render takes.
  const uint32_t kMaxSpp = (1u << 30) >> std::min(options.ladderSteps, 30u);
  uint32_t spp = uint32_t(std::max(1.0, baseSpp * options.scale));
  if (!(options.pointSeconds > 0)) return spp;
  while (spp < kMaxSpp) {
    const double seconds = secondsAt(spp);
    if (seconds >= options.pointSeconds) break;
    // Jump by the power of two the time ratio asks for (2 to 64 at a time): a few probes, not one per doubling.
    const double ratio = seconds > 0 ? options.pointSeconds / seconds : 64.0;
    const uint32_t factor = uint32_t(std::clamp(std::exp2(std::ceil(std::log2(ratio))), 2.0, 64.0));
    spp = uint32_t(std::min<uint64_t>(kMaxSpp, uint64_t(spp) * factor));
  }
  return spp;
}

uint32_t BenchOptions::scaledSide(uint32_t side) const {
  return std::max(8u, uint32_t(std::lround(side * std::sqrt(scale))));
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double peakHostMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

void plotBenchCsv(const std::filesystem::path& csv, const std::filesystem::path& png,
                  const std::function<void(const std::string&)>& log) {
  // The script goes beside the CSV, so that the run directory can be re-plotted by hand.
  const std::filesystem::path plot = csv.parent_path() / "plot_bench.py";
  writeFileAtomic(plot, kPlotBenchScript);
  // Debian's interpreter, where tools/setup installed matplotlib (a user's PATH may list another).
  std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string cmd = python + " '" + plot.string() + "' '" + csv.string() + "' '" + png.string() + "'";
  if (std::system(cmd.c_str()) != 0 && log) log("plot skipped: python3 with matplotlib is needed");
}

}  // namespace vktg
