// Pieces the benchmarks share: gates by name, medians, relMSE, peak memory, and the plot script.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "vktg/gate.h"

namespace vktg {

Gate gaussianGate(double mu, double sigma);
Gate boxGate(double a, double b);
double median(std::vector<double> values);
// relMSE = mean over pixels of (x - r)^2 / (r^2 + eps), eps = 1e-2 mean(r)^2 (0 for one pixel):
// the usual definition, made scale-free so dark pixels do not dominate.
double relMse(const std::vector<float>& x, const std::vector<float>& reference);
double peakHostMiB();
// Plots a bench CSV (scene, gate, estimator, spp, seconds, relmse, ...) with tools/plot_bench.py.
void plotBenchCsv(const std::filesystem::path& csv, const std::filesystem::path& png,
                  const std::function<void(const std::string&)>& log);

}  // namespace vktg
