// Fixed-point selection CDFs (src/scene/selection_cdf.h) and the light CDF built with one: each
// item's interval of selection numbers is as near its share as rounding allows, never empty, and
// the intervals tile [0, scale); the lights' CDF and pmfs are the intervals' ends and widths as
// floats, exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "scene/selection_cdf.h"
#include "vktg/error.h"
#include "vktg/prepared_scene.h"

namespace vktg {
namespace {

// Widths of the intervals, checking that they tile [0, scale) with none empty.
std::vector<uint64_t> widthsOf(const std::vector<uint64_t>& ends, uint64_t scale) {
  std::vector<uint64_t> widths;
  uint64_t start = 0;
  for (uint64_t end : ends) {
    EXPECT_GT(end, start);
    widths.push_back(end - start);
    start = end;
  }
  EXPECT_EQ(start, scale);
  return widths;
}

TEST(SelectionCdf, EachIntervalIsItsShareToWithinOneNumber) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> weight(0.1, 3.0);
  std::vector<double> weights(100000);
  double total = 0;
  for (double& w : weights) total += w = weight(rng);
  const uint64_t scale = uint64_t(1) << 24;  // about 170 numbers per item
  const std::vector<uint64_t> widths = widthsOf(selectionIntervalEnds(weights, scale), scale);
  double worst = 0;
  for (size_t i = 0; i < weights.size(); ++i) worst = std::max(worst, std::abs(double(widths[i]) - weights[i] / total * double(scale)));
  // Both ends rounded to the nearest integer: off by less than one (plus the CDF's summing in double).
  EXPECT_LT(worst, 1.0 + 1e-6);
}

TEST(SelectionCdf, AnItemBelowOneNumberGetsOneAndTheOthersGiveItUp) {
  const uint64_t scale = 1000;
  const std::vector<uint64_t> widths = widthsOf(selectionIntervalEnds({0.0, 1e-9, 500.0, 0.0, 500.0, 0.0}, scale), scale);
  EXPECT_EQ(widths, (std::vector<uint64_t>{1, 1, 498, 1, 498, 1}));
}

TEST(SelectionCdf, MoreItemsThanNumbersIsAnError) {
  EXPECT_THROW(selectionIntervalEnds(std::vector<double>(9, 1.0), 8), std::length_error);
  EXPECT_EQ(widthsOf(selectionIntervalEnds(std::vector<double>(8, 1.0), 8), 8), std::vector<uint64_t>(8, 1));
}

// A light among 200,000 emitting triangles (about 74 of the shaders' 2^24 numbers each): the
// CDF's ends are multiples of 2^-24 and each pmf is exactly its interval's width, so a light is
// drawn with exactly the probability its sample divides by. (With the CDF rounded to float and
// pmfs from the powers, the two differed by up to a number in 74.)
TEST(SelectionCdf, LightsAreDrawnWithExactlyTheirPmf) {
  Scene scene = parseSceneJson(R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "lights": [{"type": "point", "position": [0, 2, 2], "intensity": 1}],
    "shapes": []})", "lights.json", ".");
  Shape glow;
  glow.name = "glow";
  glow.emission = 2.0f;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  for (uint32_t t = 0; t < 200000; ++t) {
    const glm::vec3 corner(coordinate(rng), coordinate(rng), coordinate(rng));
    glow.positions.insert(glow.positions.end(), {corner, corner + glm::vec3(0.01f, 0, 0), corner + glm::vec3(0, 0.01f * (1.5f + coordinate(rng)), 0)});
    glow.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  scene.shapes.push_back(glow);
  const PreparedScene prepared = prepareScene(scene);
  ASSERT_EQ(prepared.lights.size(), 200001u);
  const double scale = 16777216.0;
  double start = 0;
  for (size_t i = 0; i < prepared.lights.size(); ++i) {
    const double end = double(prepared.lights[i].cdf) * scale;
    ASSERT_EQ(end, std::floor(end)) << "light " << i;
    ASSERT_GT(end, start) << "light " << i;
    ASSERT_EQ(double(prepared.lights[i].pmf) * scale, end - start) << "light " << i;
    start = end;
  }
  EXPECT_EQ(start, scale);
}

// Each emitter's power fits a float, the sum does not: the device divides by it as a float, so
// preparation refuses the scene. (The scene parser refuses such a file first; a scene built in
// code, or a glTF file's, reaches preparation.)
TEST(SelectionCdf, TotalPowerPastTheFloatRangeIsAnError) {
  Scene scene = parseSceneJson(R"({"version": 1,
    "camera": {"type": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0], "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"name": "lamp", "type": "rectangle", "material": "m", "emission": 1e38, "transform": {"scale": 0.5}}]})",
                               "bright.json", ".");
  Shape second = scene.shapes[0];
  second.name = "lamp2";
  for (glm::vec3& p : second.positions) p.z += 1.0f;
  scene.shapes.push_back(second);
  try {
    prepareScene(scene);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("emitted power"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vktg
