// Runs of the experiments under experiments/ for their reduced tests: the parameter error per
// iteration, and a summary of its end robust to Adam's oscillation about the optimum.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "optimize/optimize.h"

namespace vktg::test {

// What `vktg optimize EXPERIMENT --out OUT` passes to vktg::optimize and Optimization.
OptimizeOptions optimizeOptions(const std::filesystem::path& experiment, const std::filesystem::path& out);

// Whether two runs' numbers are the same bits (not merely equal: -0 and 0 differ, NaNs compare).
bool sameBits(const std::vector<double>& a, const std::vector<double>& b);

// Runs `experiment` for `iterations` into `out` and returns log.csv's parameter_error column.
std::vector<double> experimentParameterErrors(const std::filesystem::path& experiment, const std::filesystem::path& out,
                                              uint32_t iterations);

// An experiment's recovery: its parameter error at the start and at the end (medianOfLast10) after
// `iterations`; both are printed.
struct Recovery {
  double start = 0, end = 0;
};
Recovery runRecovery(const std::filesystem::path& experiment, const std::filesystem::path& out, uint32_t iterations);

// An experiment's contrast: the variant expected to recover the parameters and the weaker one, run
// from the same start (checked), each summarised by medianOfLast10 of its parameter error.
struct Contrast {
  double start = 0, strong = 0, weak = 0;
};
Contrast runContrast(const std::filesystem::path& strong, uint32_t strongIterations, const std::filesystem::path& weak,
                     uint32_t weakIterations, const std::filesystem::path& out);

// The median of the last 10 values (Adam oscillates about its optimum by about its learning rate).
double medianOfLast10(std::vector<double> values);

}  // namespace vktg::test
