// Adam and SGD with momentum on the host, in double precision and a fixed order of operations, so
// that a run restored from a checkpoint continues bit for bit.
#include "opt/optimizer.h"

#include <algorithm>
#include <cmath>

#include "vktg/error.h"

namespace vktg {
namespace {

// Margin an open end of a range keeps: relative to the end, at least kMinOpenMargin.
constexpr double kOpenMargin = 1e-6;
constexpr double kMinOpenMargin = 1e-9;

double openMargin(double end) { return std::max(kMinOpenMargin, kOpenMargin * std::abs(end)); }

// The schedule's decay after `steps` steps.
double decayFactor(const ScheduleSpec& schedule, uint64_t steps) {
  switch (schedule.type) {
    case ScheduleType::Constant: return 1.0;
    case ScheduleType::Exponential: return std::pow(schedule.decay, double(steps));
    case ScheduleType::Step: return std::pow(schedule.decay, double(steps / std::max<uint32_t>(1, schedule.every)));
  }
  return 1.0;
}

// The factor the schedule applies to every learning rate after `steps` steps: its decay, ramped up
// over the warm-up.
double scheduleFactor(const ScheduleSpec& schedule, uint64_t steps) {
  const double warmup = steps < schedule.warmup ? double(steps + 1) / double(schedule.warmup) : 1.0;
  return warmup * decayFactor(schedule, steps);
}

void requireSize(const char* what, size_t size, size_t expected) {
  if (size != expected)
    fail("", "optimizer", std::string(what) + " has " + std::to_string(size) + " values for " +
                              std::to_string(expected) + " parameters");
}

}  // namespace

Optimizer::Optimizer(const OptimizerSpec& spec, const std::vector<ExperimentParameter>& parameters)
    : m_spec(spec), m_parameters(parameters) {
  m_baseRates.reserve(parameters.size());
  for (const ExperimentParameter& p : parameters) {
    double rate = spec.learningRate;
    size_t group = 0;
    if (p.group != "default") {
      const auto entry = std::find_if(spec.groupRates.begin(), spec.groupRates.end(),
                                      [&](const auto& e) { return e.first == p.group; });
      if (entry == spec.groupRates.end())
        fail("", "optimizer.groups", "parameter \"" + p.name + "\" is in group \"" + p.group + "\", which has no learning rate");
      rate = entry->second;
      group = 1 + size_t(entry - spec.groupRates.begin());
    }
    m_baseRates.push_back(rate);
    m_groupOf.push_back(group);
  }
  m_state.first.assign(parameters.size(), 0.0);
  if (spec.type == OptimizerType::Adam) m_state.second.assign(parameters.size(), 0.0);
}

double Optimizer::learningRate(size_t parameter) const {
  return m_baseRates.at(parameter) * scheduleFactor(m_spec.schedule, m_state.steps);
}

void Optimizer::step(std::vector<double>& theta, const std::vector<double>& gradient) {
  const size_t count = m_parameters.size();
  requireSize("θ", theta.size(), count);
  requireSize("the gradient", gradient.size(), count);
  // A NaN would enter the moments and stay there for the rest of the run: stop before any change.
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(gradient[i]))
      fail("", "optimizer", "the gradient of parameter \"" + m_parameters[i].name + "\" is not finite (" +
                                std::to_string(gradient[i]) + ")");

  const double factor = scheduleFactor(m_spec.schedule, m_state.steps);
  const double t = double(m_state.steps + 1);
  // Kingma & Ba (2015), Algorithm 1: bias-corrected moments, epsilon added to sqrt(v-hat).
  const double firstCorrection = 1.0 - std::pow(m_spec.beta1, t);
  const double secondCorrection = 1.0 - std::pow(m_spec.beta2, t);
  const bool adam = m_spec.type == OptimizerType::Adam;
  // Uniform Adam: each group's largest second moment after this step, the normaliser of all of it.
  std::vector<double> groupSecond(m_spec.groupRates.size() + 1, 0.0);
  if (adam && m_spec.uniform)
    for (size_t i = 0; i < count; ++i) {
      const double v = m_spec.beta2 * m_state.second[i] + (1.0 - m_spec.beta2) * gradient[i] * gradient[i];
      groupSecond[m_groupOf[i]] = std::max(groupSecond[m_groupOf[i]], v);
    }
  // One parameter's step: its moments and value, updated in place.
  auto stepOne = [&](size_t i, double& m, double& v, double& value) {
    const double rate = m_baseRates[i] * factor;
    if (adam) {
      m = m_spec.beta1 * m + (1.0 - m_spec.beta1) * gradient[i];
      v = m_spec.beta2 * v + (1.0 - m_spec.beta2) * gradient[i] * gradient[i];
      const double mHat = m / firstCorrection;
      const double vHat = (m_spec.uniform ? groupSecond[m_groupOf[i]] : v) / secondCorrection;
      value -= rate * mHat / (std::sqrt(vHat) + m_spec.epsilon);
    } else {
      m = m_spec.momentum * m + gradient[i];
      value -= rate * m;
    }
    value = projectToRange(value, m_parameters[i].range);
  };
  // Every step is tried on copies first and taken only if all stay finite: a finite but huge
  // gradient can still overflow a moment or θ (SGD's velocity grows without bound), and an infinite
  // θ would reach the scene as vertices at infinity. θ and the state then stay as they were.
  for (size_t i = 0; i < count; ++i) {
    double m = m_state.first[i], v = adam ? m_state.second[i] : 0.0, value = theta[i];
    stepOne(i, m, v, value);
    if (!std::isfinite(m) || !std::isfinite(v) || !std::isfinite(value))
      fail("", "optimizer", "the step of parameter \"" + m_parameters[i].name + "\" overflows (gradient " +
                                std::to_string(gradient[i]) + ", learning rate " + std::to_string(m_baseRates[i] * factor) +
                                "): lower its learning rate or scale the loss; θ is left as it was");
  }
  double unused = 0.0;
  for (size_t i = 0; i < count; ++i) stepOne(i, m_state.first[i], adam ? m_state.second[i] : unused, theta[i]);
  ++m_state.steps;
}

void Optimizer::restore(const OptimizerState& state) {
  const size_t count = m_parameters.size();
  requireSize("the saved first moments", state.first.size(), count);
  requireSize("the saved second moments", state.second.size(), m_spec.type == OptimizerType::Adam ? count : 0);
  m_state = state;
}

double projectToRange(double theta, const ParameterRange& range) {
  double low = range.low, high = range.high;
  if (range.lowOpen && std::isfinite(low)) low += openMargin(low);
  if (range.highOpen && std::isfinite(high)) high -= openMargin(high);
  // A range narrower than its margins: its middle is the only safe value.
  if (low > high) return 0.5 * (range.low + range.high);
  return std::clamp(theta, low, high);
}

}  // namespace vktg
