#include "support/experiment_run.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "optimize/optimize.h"
#include "opt/run_directory.h"
#include "support/gpu_context.h"

#include <gtest/gtest.h>

namespace vktg::test {

OptimizeOptions optimizeOptions(const std::filesystem::path& experiment, const std::filesystem::path& out) {
  OptimizeOptions o;
  o.experiment = experiment;
  o.runDirectory = out;
  return o;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

std::vector<double> experimentParameterErrors(const std::filesystem::path& experiment, const std::filesystem::path& out,
                                              uint32_t iterations) {
  OptimizeOptions o;
  o.experiment = experiment;
  o.runDirectory = out;
  o.iterations = iterations;
  optimize(testContext(), o);
  return readLogColumns(out / "log.csv").at("parameter_error");
}

Recovery runRecovery(const std::filesystem::path& experiment, const std::filesystem::path& out, uint32_t iterations) {
  const std::vector<double> errors = experimentParameterErrors(experiment, out, iterations);
  const Recovery r{errors.front(), medianOfLast10(errors)};
  std::printf("  parameter error from %.5f: %.5f after %u iterations\n", r.start, r.end, iterations);
  return r;
}

Contrast runContrast(const std::filesystem::path& strong, uint32_t strongIterations, const std::filesystem::path& weak,
                     uint32_t weakIterations, const std::filesystem::path& out) {
  const std::vector<double> strongErrors = experimentParameterErrors(strong, out / "strong", strongIterations);
  const std::vector<double> weakErrors = experimentParameterErrors(weak, out / "weak", weakIterations);
  EXPECT_NEAR(strongErrors.front(), weakErrors.front(), 1e-12) << "the variants must start from the same parameters";
  return {strongErrors.front(), medianOfLast10(strongErrors), medianOfLast10(weakErrors)};
}

double medianOfLast10(std::vector<double> values) {
  values.erase(values.begin(), values.end() - std::min<size_t>(10, values.size()));
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace vktg::test
