// Image losses: values on small images worked out by hand, adjoint images against central finite
// differences of the loss in every pixel, and the errors for images that do not match.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "opt/loss.h"
#include "support/file_test.h"
#include "vktg/error.h"

namespace vktg {
namespace {

using test::expectError;

ImageSet image(uint32_t width, uint32_t height, std::vector<std::vector<float>> layers) {
  ImageSet set{width, height, {}};
  for (size_t l = 0; l < layers.size(); ++l) set.layers.push_back({"layer" + std::to_string(l), std::move(layers[l])});
  return set;
}

LossSpec spec(LossType type, double epsilon = 1e-2) { return LossSpec{type, epsilon}; }

TEST(Loss, ValuesByHand) {
  // Two layers of 2 x 1 pixels: differences I - T = (1, -2) and (0.5, 0).
  const ImageSet rendered = image(2, 1, {{2, 0}, {1.5f, 3}});
  const ImageSet target = image(2, 1, {{1, 2}, {1, 3}});
  // L2: mean of 1, 4, 0.25, 0 = 1.3125; weight 2.
  EXPECT_DOUBLE_EQ(imageLoss(spec(LossType::L2), rendered, target, 2.0), 2.0 * 5.25 / 4);
  // L1: mean of 1, 2, 0.5, 0.
  EXPECT_DOUBLE_EQ(imageLoss(spec(LossType::L1), rendered, target, 1.0), 3.5 / 4);
  // Relative L2 with epsilon 0.5: mean |T| = 7/4, floor (0.5 * 7/4)^2 = 0.765625.
  const double floor = 0.765625;
  const double expected = (1 / (1 + floor) + 4 / (4 + floor) + 0.25 / (1 + floor) + 0) / 4;
  EXPECT_DOUBLE_EQ(imageLoss(spec(LossType::RelativeL2, 0.5), rendered, target, 1.0), expected);
}

TEST(Loss, AdjointHasTheRenderedLayoutAndIsTheDerivative) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.1f, 2.0f);
  std::vector<std::vector<float>> renderedLayers(2, std::vector<float>(12)), targetLayers(2, std::vector<float>(12));
  for (auto* layers : {&renderedLayers, &targetLayers})
    for (auto& layer : *layers)
      for (float& v : layer) v = uniform(rng);
  const ImageSet rendered = image(4, 3, renderedLayers), target = image(4, 3, targetLayers);
  for (LossType type : {LossType::L2, LossType::L1, LossType::RelativeL2}) {
    const LossSpec s = spec(type, 0.3);
    ImageSet adjoint;
    const double weight = 1.7;
    const double loss = imageLoss(s, rendered, target, weight, &adjoint);
    EXPECT_EQ(loss, imageLoss(s, rendered, target, weight));
    ASSERT_EQ(adjoint.width, 4u);
    ASSERT_EQ(adjoint.height, 3u);
    ASSERT_EQ(adjoint.layers.size(), 2u);
    EXPECT_EQ(adjoint.layers[1].name, "layer1");
    for (size_t l = 0; l < 2; ++l)
      for (size_t i = 0; i < 12; ++i) {
        // Central differences in double: the loss is a polynomial (or |x|, away from its kink) in I.
        const float h = 1e-3f;
        ImageSet plus = rendered, minus = rendered;
        plus.layers[l].pixels[i] += h;
        minus.layers[l].pixels[i] -= h;
        const double step = double(plus.layers[l].pixels[i]) - double(minus.layers[l].pixels[i]);
        const double fd = (imageLoss(s, plus, target, weight) - imageLoss(s, minus, target, weight)) / step;
        EXPECT_NEAR(adjoint.layers[l].pixels[i], fd, 1e-5 * std::max(1.0, std::abs(fd))) << int(type) << " " << l << " " << i;
      }
  }
}

TEST(Loss, L1HasZeroSlopeAtEquality) {
  ImageSet adjoint;
  const ImageSet same = image(1, 1, {{0.5f}});
  EXPECT_EQ(imageLoss(spec(LossType::L1), same, same, 1.0, &adjoint), 0.0);
  EXPECT_EQ(adjoint.layers[0].pixels[0], 0.0f);
  imageLoss(spec(LossType::L1), image(2, 1, {{1, 0}}), image(2, 1, {{0, 1}}), 1.0, &adjoint);
  EXPECT_EQ(adjoint.layers[0].pixels, (std::vector<float>{0.5f, -0.5f}));
}

TEST(Loss, LossDoesNotScaleWithResolutionOrStackLength) {
  const ImageSet small = image(1, 1, {{2}}), smallTarget = image(1, 1, {{1}});
  const ImageSet large = image(3, 2, {std::vector<float>(6, 2), std::vector<float>(6, 2)});
  const ImageSet largeTarget = image(3, 2, {std::vector<float>(6, 1), std::vector<float>(6, 1)});
  for (LossType type : {LossType::L2, LossType::L1, LossType::RelativeL2})
    EXPECT_DOUBLE_EQ(imageLoss(spec(type), small, smallTarget, 1.0), imageLoss(spec(type), large, largeTarget, 1.0));
}

TEST(Loss, MismatchedImagesAreErrors) {
  const ImageSet a = image(2, 1, {{1, 2}});
  expectError([&] { imageLoss(spec(LossType::L2), a, image(1, 2, {{1, 2}}), 1.0); }, {"2x1 with 1 layer(s)", "1x2 with 1 layer(s)"});
  expectError([&] { imageLoss(spec(LossType::L2), a, image(2, 1, {{1, 2}, {3, 4}}), 1.0); }, {"2x1 with 2 layer(s)"});
  expectError([&] { imageLoss(spec(LossType::L2), a, image(2, 1, {{1}}), 1.0); }, {"wrong pixel count"});
  expectError([&] { imageLoss(spec(LossType::RelativeL2), a, image(2, 1, {{0, 0}}), 1.0); }, {"relative_l2", "non-zero pixel"});
}

}  // namespace
}  // namespace vktg
