// Pieces the benchmarks share: gates by name, medians, variances across runs, peak memory, and the
// plot script (relMSE: render/relative_error.h).
#pragma once
#include <filesystem>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "render/relative_error.h"
#include "vktg/gate.h"

namespace vktg {

// Settings shared by the `vktg bench` commands.
struct BenchOptions {
  std::filesystem::path outDir;  // run directory (references are cached there)
  uint32_t runs = 3;             // repetitions per point (medians are reported)
  uint32_t ladderSteps = 5;      // spp doubles this many times from the base
  double scale = 1.0;            // multiplies every spp (quick runs use < 1)
  // The shortest a ladder's first point may take: on a fast device a fixed sample count measures
  // launch overhead, not the estimator (0: take the sample counts as they are).
  double pointSeconds = 0.05;
  uint64_t memoryBudget = 0;  // 0: the device's default
  std::function<void(const std::string&)> log;

  void say(const std::string& line) const {
    if (log) log(line);
  }
  // An image side of `side` pixels at full scale: the pixel count follows `scale` (at least 8 a side).
  uint32_t scaledSide(uint32_t side) const;
};

// The first sample count of a ladder: `baseSpp` × scale (at least 1), multiplied by powers of two
// until one run at it, timed by `secondsAt(spp)`, takes options.pointSeconds (at most 2^30 spp at
// the ladder's last point).
uint32_t firstLadderSpp(double baseSpp, const BenchOptions& options, const std::function<double(uint32_t spp)>& secondsAt);

Gate gaussianGate(double mu, double sigma);
Gate boxGate(double a, double b);
double median(std::vector<double> values);
// Each element's sample variance across `runs` (at least two, all of one length): the sum of squared
// deviations from the element's mean over n - 1.
template <class T>
std::vector<double> varianceAcrossRuns(const std::vector<std::vector<T>>& runs) {
  std::vector<double> variance(runs.front().size());
  for (size_t i = 0; i < variance.size(); ++i) {
    double mean = 0, squares = 0;
    for (const auto& run : runs) mean += run[i];
    mean /= double(runs.size());
    for (const auto& run : runs) squares += (run[i] - mean) * (run[i] - mean);
    variance[i] = squares / double(runs.size() - 1);
  }
  return variance;
}
double peakHostMiB();
// Plots a bench CSV (scene, gate, estimator, spp, seconds, relmse, ...) with tools/plot_bench.py
// (compiled in, and written beside the CSV).
void plotBenchCsv(const std::filesystem::path& csv, const std::filesystem::path& png,
                  const std::function<void(const std::string&)>& log);

}  // namespace vktg
