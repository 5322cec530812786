// Optimisers: Adam and SGD steps against values worked out by hand, learning-rate groups and
// schedules, projection onto valid ranges (open ends keep a margin), bit-exact continuation from a
// restored state, and the errors.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "opt/optimizer.h"
#include "support/file_test.h"
#include "vktg/error.h"

namespace vktg {
namespace {

using test::expectError;

std::vector<ExperimentParameter> parameters(size_t count, const std::string& group = "default") {
  std::vector<ExperimentParameter> out(count);
  for (size_t i = 0; i < count; ++i) {
    out[i].name = "p" + std::to_string(i);
    out[i].group = group;
  }
  return out;
}

OptimizerSpec adam(double rate) {
  OptimizerSpec spec;
  spec.type = OptimizerType::Adam;
  spec.learningRate = rate;
  return spec;
}

OptimizerSpec sgd(double rate, double momentum) {
  OptimizerSpec spec;
  spec.type = OptimizerType::Sgd;
  spec.learningRate = rate;
  spec.momentum = momentum;
  return spec;
}

TEST(Optimizer, AdamStepsByHand) {
  // lr 0.1, beta1 0.9, beta2 0.999, epsilon 1e-8, theta0 = 1, gradients 0.5, -1, 0.25.
  // Step 1: m = 0.05, v = 0.00025, m^ = 0.5, v^ = 0.25: theta = 1 - 0.1 * 0.5 / (0.5 + 1e-8) = 0.900000002.
  // Step 2: m = 0.045 - 0.1 = -0.055, v = 0.00024975 + 0.001, m^ = -0.055 / 0.19,
  //         v^ = 0.00124975 / 0.001999: theta = 0.93661035424056...
  Optimizer optimizer(adam(0.1), parameters(1));
  std::vector<double> theta{1.0};
  const double expected[] = {0.900000002, 0.9366103542405654, 0.9502794203389762};
  const double gradients[] = {0.5, -1.0, 0.25};
  for (int i = 0; i < 3; ++i) {
    optimizer.step(theta, {gradients[i]});
    EXPECT_NEAR(theta[0], expected[i], 1e-15) << "step " << i + 1;
  }
  EXPECT_EQ(optimizer.state().steps, 3u);
  EXPECT_NEAR(optimizer.state().first[0], -0.0245, 1e-17);
  EXPECT_NEAR(optimizer.state().second[0], 0.001311000250000001, 1e-18);
}

TEST(Optimizer, AdamFirstStepIsTheLearningRateWhateverTheGradientScale) {
  // Bias correction makes the first step lr * g / (|g| + epsilon): scale-free.
  for (double g : {1e-3, 1.0, 1e4}) {
    Optimizer optimizer(adam(0.02), parameters(1));
    std::vector<double> theta{0.0};
    optimizer.step(theta, {-g});
    EXPECT_NEAR(theta[0], 0.02, 0.02 * 1e-8 / g + 1e-16);
  }
}

// Uniform Adam divides by the largest second moment of the group, so the step keeps the gradient's
// shape: lr 0.1, gradients 1 and 0.1 in one group: v^ = g^2 on the first step, normalised by 1.
// A parameter of another group is normalised by its own group's moments.
TEST(Optimizer, UniformAdamDividesByTheGroupsLargestSecondMoment) {
  OptimizerSpec spec = adam(0.1);
  spec.uniform = true;
  spec.groupRates = {{"other", 0.2}};
  std::vector<ExperimentParameter> ps = parameters(3);
  ps[2].group = "other";
  Optimizer optimizer(spec, ps);
  std::vector<double> theta{0.0, 0.0, 0.0};
  optimizer.step(theta, {1.0, 0.1, 0.01});
  EXPECT_NEAR(theta[0], -0.1, 1e-9);
  EXPECT_NEAR(theta[1], -0.01, 1e-9);
  EXPECT_NEAR(theta[2], -0.2, 1e-6);  // alone in its group: the plain Adam step, the rate
  // Per-parameter Adam would move both of the first group by the rate.
  Optimizer plain(adam(0.1), parameters(2));
  std::vector<double> same{0.0, 0.0};
  plain.step(same, {1.0, 0.1});
  EXPECT_NEAR(same[1], -0.1, 1e-7);  // epsilon 1e-8 against |g| = 0.1
}

TEST(Optimizer, SgdWithMomentumByHand) {
  // v = 0.9 v + g, theta -= 0.1 v: v = 0.5, -0.55, -0.495; theta = 0.95, 1.005, 1.0545.
  Optimizer optimizer(sgd(0.1, 0.9), parameters(1));
  std::vector<double> theta{1.0};
  optimizer.step(theta, {0.5});
  EXPECT_DOUBLE_EQ(theta[0], 0.95);
  optimizer.step(theta, {-1.0});
  EXPECT_DOUBLE_EQ(theta[0], 1.005);
  optimizer.step(theta, {0.0});
  EXPECT_DOUBLE_EQ(theta[0], 1.0545);
  EXPECT_DOUBLE_EQ(optimizer.state().first[0], -0.495);
  EXPECT_TRUE(optimizer.state().second.empty());
}

TEST(Optimizer, GroupsHaveTheirOwnLearningRates) {
  OptimizerSpec spec = sgd(0.1, 0.0);
  spec.groupRates = {{"fast", 2.0}, {"slow", 0.001}};
  std::vector<ExperimentParameter> ps = parameters(3);
  ps[1].group = "fast";
  ps[2].group = "slow";
  Optimizer optimizer(spec, ps);
  EXPECT_EQ(optimizer.learningRate(0), 0.1);
  EXPECT_EQ(optimizer.learningRate(1), 2.0);
  EXPECT_EQ(optimizer.learningRate(2), 0.001);
  std::vector<double> theta{0, 0, 0};
  optimizer.step(theta, {1, 1, 1});
  EXPECT_EQ(theta, (std::vector<double>{-0.1, -2.0, -0.001}));
  ps[2].group = "missing";
  expectError([&] { Optimizer(spec, ps); }, {"\"p2\"", "group \"missing\"", "no learning rate"});
}

TEST(Optimizer, ExponentialScheduleDecaysEveryStep) {
  OptimizerSpec spec = sgd(1.0, 0.0);
  spec.schedule = {ScheduleType::Exponential, 0.5, 1};
  Optimizer optimizer(spec, parameters(1));
  std::vector<double> theta{0.0};
  // The step at iteration i uses lr * 0.5^i: -1, -0.5, -0.25.
  const double expected[] = {-1.0, -1.5, -1.75};
  for (double e : expected) {
    optimizer.step(theta, {1.0});
    EXPECT_EQ(theta[0], e);
  }
  EXPECT_EQ(optimizer.learningRate(0), 0.125);
}

TEST(Optimizer, StepScheduleDecaysEveryNSteps) {
  OptimizerSpec spec = adam(0.8);
  spec.schedule = {ScheduleType::Step, 0.5, 3};
  Optimizer optimizer(spec, parameters(1));
  std::vector<double> theta{0.0};
  const double expected[] = {0.8, 0.8, 0.8, 0.4, 0.4, 0.4, 0.2};
  for (double rate : expected) {
    EXPECT_EQ(optimizer.learningRate(0), rate) << "after " << optimizer.state().steps << " steps";
    optimizer.step(theta, {1.0});
  }
}

TEST(Optimizer, WarmupRampsAnyScheduleOverItsFirstSteps) {
  OptimizerSpec spec = sgd(0.8, 0.0);
  spec.schedule = {ScheduleType::Exponential, 0.5, 1, 4};
  Optimizer optimizer(spec, parameters(1));
  std::vector<double> theta{0.0};
  // Step i: 0.8 * 0.5^i, times (i + 1) / 4 for the first four.
  const double expected[] = {0.2, 0.2, 0.15, 0.1, 0.05, 0.025};
  for (double rate : expected) {
    EXPECT_DOUBLE_EQ(optimizer.learningRate(0), rate) << "after " << optimizer.state().steps << " steps";
    optimizer.step(theta, {1.0});
  }
  spec.schedule = {ScheduleType::Constant, 1.0, 1, 2};
  Optimizer constant(spec, parameters(1));
  EXPECT_DOUBLE_EQ(constant.learningRate(0), 0.4);
  constant.step(theta, {1.0});
  EXPECT_DOUBLE_EQ(constant.learningRate(0), 0.8);
}

TEST(Optimizer, ConstantScheduleKeepsTheRate) {
  Optimizer optimizer(sgd(0.3, 0.5), parameters(1));
  std::vector<double> theta{0.0};
  for (int i = 0; i < 5; ++i) optimizer.step(theta, {1.0});
  EXPECT_EQ(optimizer.learningRate(0), 0.3);
}

TEST(Projection, ClosedEndsClampExactly) {
  const ParameterRange albedo{-0.5, 0.5, false, false};
  EXPECT_EQ(projectToRange(0.7, albedo), 0.5);
  EXPECT_EQ(projectToRange(-3.0, albedo), -0.5);
  EXPECT_EQ(projectToRange(0.25, albedo), 0.25);
  EXPECT_EQ(projectToRange(0.5, albedo), 0.5);
  EXPECT_EQ(projectToRange(1e300, ParameterRange{}), 1e300);
}

TEST(Projection, OpenEndsKeepAMargin) {
  // ior 1.5 + theta > 1: theta > -0.5, kept 1e-6 * 0.5 inside.
  const ParameterRange ior{-0.5, INFINITY, true, false};
  EXPECT_EQ(projectToRange(-0.7, ior), -0.5 + 5e-7);
  EXPECT_EQ(projectToRange(-0.5, ior), -0.5 + 5e-7);
  EXPECT_TRUE(ior.contains(projectToRange(-0.5, ior)));
  EXPECT_EQ(projectToRange(-0.4, ior), -0.4);
  // The margin is at least 1e-9, also at an end of 0.
  const ParameterRange positive{0.0, 1.0, true, true};
  EXPECT_EQ(projectToRange(-1.0, positive), 1e-9);
  EXPECT_EQ(projectToRange(2.0, positive), 1.0 - 1e-6);
  // A range narrower than its margins: its middle.
  EXPECT_EQ(projectToRange(3.0, ParameterRange{0.0, 1e-9, true, true}), 0.5e-9);
}

TEST(Optimizer, StepsAreProjectedOntoEachParametersRange) {
  std::vector<ExperimentParameter> ps = parameters(2);
  ps[0].range = {-0.5, 0.5, false, false};
  ps[1].range = {-0.2, INFINITY, true, false};
  Optimizer optimizer(sgd(1.0, 0.0), ps);
  std::vector<double> theta{0.4, 0.0};
  optimizer.step(theta, {-1.0, 1.0});
  EXPECT_EQ(theta[0], 0.5);
  EXPECT_DOUBLE_EQ(theta[1], -0.2 + 2e-7);
}

TEST(Optimizer, RestoredStateContinuesBitForBit) {
  OptimizerSpec uniform = adam(0.05);
  uniform.uniform = true;
  for (const OptimizerSpec& spec : {adam(0.05), uniform, sgd(0.05, 0.8)}) {
    Optimizer uninterrupted(spec, parameters(3));
    std::vector<double> theta{0.1, -0.2, 0.3};
    auto gradient = [](int i) { return std::vector<double>{std::sin(i), std::cos(3.0 * i), 1.0 / (i + 1)}; };
    for (int i = 0; i < 4; ++i) uninterrupted.step(theta, gradient(i));
    const OptimizerState saved = uninterrupted.state();
    std::vector<double> resumedTheta = theta;
    Optimizer resumed(spec, parameters(3));
    resumed.restore(saved);
    EXPECT_EQ(resumed.state().steps, 4u);
    for (int i = 4; i < 9; ++i) {
      uninterrupted.step(theta, gradient(i));
      resumed.step(resumedTheta, gradient(i));
    }
    EXPECT_EQ(std::memcmp(theta.data(), resumedTheta.data(), sizeof(double) * 3), 0);
    EXPECT_EQ(resumed.state().first, uninterrupted.state().first);
    EXPECT_EQ(resumed.state().second, uninterrupted.state().second);
  }
}

TEST(Optimizer, AStepThatOverflowsIsRefusedAndLeavesThetaAndStateAsTheyWere) {
  // SGD: a finite gradient times a large rate leaves the doubles.
  Optimizer plain(sgd(1e10, 0.9), parameters(2));
  std::vector<double> theta{1.0, 2.0};
  plain.step(theta, {1.0, 1.0});
  const OptimizerState before = plain.state();
  const std::vector<double> thetaBefore = theta;
  expectError([&] { plain.step(theta, {1.0, 1e300}); }, {"\"p1\"", "overflows", "learning rate", "θ is left as it was"});
  EXPECT_EQ(theta, thetaBefore);
  EXPECT_EQ(plain.state().steps, before.steps);
  EXPECT_EQ(plain.state().first, before.first);
  // Adam: the step itself is bounded, but g^2 overflows the second moment, which would then stay
  // infinite and freeze the parameter for the rest of the run.
  Optimizer adamOptimizer(adam(0.1), parameters(1));
  std::vector<double> one{1.0};
  expectError([&] { adamOptimizer.step(one, {1e200}); }, {"\"p0\"", "overflows"});
  EXPECT_EQ(one, std::vector<double>{1.0});
  EXPECT_EQ(adamOptimizer.state().steps, 0u);
  adamOptimizer.step(one, {1e100});  // large but representable: taken
  EXPECT_NEAR(one[0], 0.9, 1e-12);
}

TEST(Optimizer, Errors) {
  Optimizer optimizer(adam(0.1), parameters(2));
  std::vector<double> theta{1.0, 2.0};
  expectError([&] { optimizer.step(theta, {1.0}); }, {"the gradient has 1 values for 2 parameters"});
  std::vector<double> shortTheta{1.0};
  expectError([&] { optimizer.step(shortTheta, {1.0, 1.0}); }, {"θ has 1 values for 2 parameters"});
  expectError([&] { optimizer.step(theta, {1.0, NAN}); }, {"\"p1\"", "not finite"});
  EXPECT_EQ(theta, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(optimizer.state().steps, 0u);
  EXPECT_EQ(optimizer.state().first, (std::vector<double>{0.0, 0.0}));
  expectError([&] { optimizer.restore(OptimizerState{1, {0.0}, {0.0, 0.0}}); }, {"first moments", "1 values for 2"});
  expectError([&] { optimizer.restore(OptimizerState{1, {0.0, 0.0}, {}}); }, {"second moments", "0 values for 2"});
  Optimizer plain(sgd(0.1, 0.9), parameters(2));
  expectError([&] { plain.restore(OptimizerState{1, {0.0, 0.0}, {0.0, 0.0}}); }, {"second moments", "2 values for 0"});
}

}  // namespace
}  // namespace vktg
