// First-order optimisers on the parameter vector θ (double precision, on the host): Adam and SGD
// with momentum (Adam optionally uniform over each group), a learning rate per parameter group, a
// schedule, and projection onto each
// parameter's valid range after every step. The state serialises exactly (checkpoints).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "opt/experiment.h"

namespace vktg {

struct OptimizerState {
  uint64_t steps = 0;
  std::vector<double> first;   // Adam m / SGD velocity
  std::vector<double> second;  // Adam v (empty for SGD)
};

class Optimizer {
 public:
  Optimizer(const OptimizerSpec& spec, const std::vector<ExperimentParameter>& parameters);
  // θ <- project(θ - step(gradient)); the step uses the learning rate of each parameter's group at
  // iteration `steps` (the schedule), then counts the step.
  void step(std::vector<double>& theta, const std::vector<double>& gradient);
  double learningRate(size_t parameter) const;  // current, after the schedule
  const OptimizerState& state() const { return m_state; }
  void restore(const OptimizerState& state);    // throws vktg::Error if the sizes do not match

 private:
  OptimizerSpec m_spec;
  std::vector<ExperimentParameter> m_parameters;
  std::vector<double> m_baseRates;
  std::vector<size_t> m_groupOf;  // learning-rate group of each parameter (0: "default"), for uniform Adam
  OptimizerState m_state;
};

// θ clamped into `range`; an open end keeps a margin of 1e-6 (relative to the end, at least 1e-9).
double projectToRange(double theta, const ParameterRange& range);

}  // namespace vktg
