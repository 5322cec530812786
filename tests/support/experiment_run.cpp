#include "support/experiment_run.h"

#include <algorithm>

#include "host/optimize.h"
#include "opt/run_directory.h"
#include "support/gpu_context.h"

namespace vktg::test {

std::vector<double> experimentParameterErrors(const std::filesystem::path& experiment, const std::filesystem::path& out,
                                              uint32_t iterations) {
  OptimizeOptions o;
  o.experiment = experiment;
  o.runDirectory = out;
  o.iterations = iterations;
  optimize(testContext(), o);
  return readLogColumns(out / "log.csv").at("parameter_error");
}

double medianOfLast10(std::vector<double> values) {
  values.erase(values.begin(), values.end() - std::min<size_t>(10, values.size()));
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace vktg::test
