// Every geometric parameter kind against central finite differences of the rendered image (common
// random numbers over seeds), on tests/data/parameter_kinds.json: a bumpy heightfield lit by a lamp,
// a small box floating above it, max depth 3. `bump` displaces three heightfield vertices, `h12`
// is one of its heights (heightfield_heights), `v0_x` one coordinate of one box vertex
// (vertex_positions) and `spin` turns the box (rotate). Under a gaussian gate the total is interior
// + edge; under a box gate the path-length-boundary term joins them. Image sums and 4 x 4 tiles are
// compared, each a t-test with the measured standard errors of both sides, Sidak-corrected (alpha
// 1e-3) over every comparison of a test. (Translations are checked in grad_edge and grad_contact.)
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/boundary_test.h"
#include "vktg/scene.h"

namespace vktg::test {
namespace {

using namespace boundary;

constexpr uint32_t kResolution = 16, kTile = 4, kFdSeeds = 16;
constexpr double kStep = 0.005;
const char* const kParameters[] = {"bump", "h12", "v0_x", "spin"};

void expectEveryKindMatchesFd(const Gate& gate) {
  Scene scene = loadScene(std::string(VKTG_SOURCE_DIR) + "/tests/data/parameter_kinds.json");
  scene.gate = gate;
  scene.render.spp = 512;
  scene.render.seed = 3;
  const size_t tiles = (kResolution / kTile) * (kResolution / kTile);
  Checker check{sidakLevel(kAlpha, std::size(kParameters) * (tiles + 1))};
  for (const char* parameter : kParameters) {
    GradientOptions options;
    options.sppEdge = 1024;
    GradientResult g = renderGradient(testRenderer(), scene, {parameter}, options);
    EXPECT_EQ(g.stats.nonFinite, 0u);
    SeedDifference fd = seedFiniteDifference(scene, parameter, kStep, kFdSeeds, RenderOptions{});
    EXPECT_EQ(fd.nonFinite, 0u);
    const LayerEstimate total = term(g.total, 0), reference = fd.layers.at(0);
    std::printf("  %s: image sums %.4f against fd %.4f (%.2f s, %.2f s)\n", parameter, sumPixels(total).mean[0],
                sumPixels(reference).mean[0], g.stats.seconds, fd.seconds);
    check.expect((std::string(parameter) + " tiles").c_str(), sumTiles(total, kResolution, kTile),
                 sumTiles(reference, kResolution, kTile));
    check.expect((std::string(parameter) + " image sum").c_str(), sumPixels(total), sumPixels(reference));
  }
}

TEST(GradParameterKinds, GaussianGate) {
  Gate gate;
  gate.type = GateType::Gaussian;
  gate.mu = 5.5;
  gate.sigma = 0.6;
  expectEveryKindMatchesFd(gate);
}

TEST(GradParameterKinds, BoxGate) {
  Gate gate;
  gate.type = GateType::Box;
  gate.a = 5.0;
  gate.b = 6.0;
  expectEveryKindMatchesFd(gate);
}

}  // namespace
}  // namespace vktg::test
