// Laplacian smoothness (value by hand, gradient against finite differences, invariance under rigid
// motions) and the large-steps solve (against a dense solve, and the properties of a smoothing
// operator), on their own and applied to an experiment's parameters.
#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "opt/regularizer.h"
#include "support/file_test.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::expectError;

const fs::path kData = fs::path(VKTG_TEST_DATA) / "optimize";

// An n x n grid of vertices in the xz-plane, two triangles per cell (as heightfields are built).
std::vector<glm::uvec3> gridTriangles(uint32_t n) {
  std::vector<glm::uvec3> triangles;
  for (uint32_t j = 0; j + 1 < n; ++j)
    for (uint32_t i = 0; i + 1 < n; ++i) {
      const uint32_t v = j * n + i;
      triangles.push_back({v, v + n, v + 1});
      triangles.push_back({v + 1, v + n, v + n + 1});
    }
  return triangles;
}

std::vector<glm::dvec3> randomPositions(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<glm::dvec3> positions(count);
  for (glm::dvec3& p : positions) p = {uniform(rng), uniform(rng), uniform(rng)};
  return positions;
}

double energyOf(const std::vector<glm::dvec3>& positions, const std::vector<glm::uvec3>& triangles, double weight) {
  std::vector<glm::dvec3> unused(positions.size(), glm::dvec3(0.0));
  return laplacianEnergy(positions, triangles, weight, unused);
}

TEST(Laplacian, EnergyOfOneTriangleByHand) {
  // Each corner's neighbours are the other two: delta = (-0.5, -0.5, 0), (1, -0.5, 0), (-0.5, 1, 0),
  // squared lengths 0.5 + 1.25 + 1.25 = 3, divided by 3 vertices, times weight 2.
  const std::vector<glm::dvec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<glm::uvec3> triangles = {{0, 1, 2}};
  std::vector<glm::dvec3> gradient(3, glm::dvec3(1.0));
  EXPECT_DOUBLE_EQ(laplacianEnergy(positions, triangles, 2.0, gradient), 2.0);
  // dE/dV_0 = 2 w / n (delta_0 - delta_1 / 2 - delta_2 / 2) = 4/3 (-0.75, -0.75, 0) = (-1, -1, 0),
  // added to the 1 already there.
  EXPECT_NEAR(gradient[0].x, 0.0, 1e-15);
  EXPECT_NEAR(gradient[0].y, 0.0, 1e-15);
  EXPECT_EQ(gradient[0].z, 1.0);
}

TEST(Laplacian, GradientMatchesFiniteDifferences) {
  const uint32_t n = 4;
  const std::vector<glm::uvec3> triangles = gridTriangles(n);
  const std::vector<glm::dvec3> positions = randomPositions(n * n, 3);
  const double weight = 0.7;
  std::vector<glm::dvec3> gradient(positions.size(), glm::dvec3(0.0));
  laplacianEnergy(positions, triangles, weight, gradient);
  const double h = 1e-6;
  for (size_t v = 0; v < positions.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      std::vector<glm::dvec3> plus = positions, minus = positions;
      plus[v][c] += h;
      minus[v][c] -= h;
      const double fd = (energyOf(plus, triangles, weight) - energyOf(minus, triangles, weight)) / (2 * h);
      EXPECT_NEAR(gradient[v][c], fd, 1e-8) << "vertex " << v << " axis " << c;
    }
}

TEST(Laplacian, RigidMotionsLeaveTheEnergyUnchanged) {
  const std::vector<glm::uvec3> triangles = gridTriangles(3);
  const std::vector<glm::dvec3> positions = randomPositions(9, 5);
  const double energy = energyOf(positions, triangles, 1.0);
  EXPECT_GT(energy, 0.01);
  std::vector<glm::dvec3> moved = positions;
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (glm::dvec3& p : moved) p = glm::dvec3(c * p.x - s * p.z, p.y, s * p.x + c * p.z) + glm::dvec3(3, -2, 1);
  EXPECT_NEAR(energyOf(moved, triangles, 1.0), energy, 1e-12);
  // Lifting the middle vertex of a flat grid off its plane raises the energy.
  std::vector<glm::dvec3> flat(9);
  for (uint32_t i = 0; i < 9; ++i) flat[i] = {double(i % 3), 0, double(i / 3)};
  std::vector<glm::dvec3> bumped = flat;
  bumped[4].y = 0.5;
  EXPECT_GT(energyOf(bumped, triangles, 1.0), energyOf(flat, triangles, 1.0));
}

TEST(Laplacian, IsolatedVerticesAndErrors) {
  const std::vector<glm::dvec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
  std::vector<glm::dvec3> gradient(4, glm::dvec3(0.0));
  EXPECT_DOUBLE_EQ(laplacianEnergy(positions, std::vector<glm::uvec3>{{0, 1, 2}}, 2.0, gradient), 2.0 * 3 / 4);
  EXPECT_EQ(gradient[3], glm::dvec3(0.0));
  expectError([&] { laplacianEnergy(positions, std::vector<glm::uvec3>{{0, 1, 4}}, 1.0, gradient); },
              {"triangle 0 names vertex 4 of a mesh with 4 vertices"});
  std::vector<glm::dvec3> shortGradient(3);
  expectError([&] { laplacianEnergy(positions, std::vector<glm::uvec3>{{0, 1, 2}}, 1.0, shortGradient); },
              {"3 entries for 4 vertices"});
}

// (I + lambda L) x = b by Gaussian elimination with partial pivoting, L from the triangles' edges.
std::vector<double> denseSolve(const std::vector<glm::uvec3>& triangles, size_t n, double lambda, std::vector<double> b) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (const glm::uvec3& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = t[c], e = t[(c + 1) % 3];
      edges.insert({std::min(a, e), std::max(a, e)});
    }
  std::vector<std::vector<double>> a(n, std::vector<double>(n, 0.0));
  for (size_t i = 0; i < n; ++i) a[i][i] = 1;
  for (const auto& [i, j] : edges) {
    a[i][i] += lambda;
    a[j][j] += lambda;
    a[i][j] -= lambda;
    a[j][i] -= lambda;
  }
  for (size_t col = 0; col < n; ++col) {
    size_t pivot = col;
    for (size_t r = col + 1; r < n; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    std::swap(a[col], a[pivot]);
    std::swap(b[col], b[pivot]);
    for (size_t r = col + 1; r < n; ++r) {
      const double f = a[r][col] / a[col][col];
      for (size_t k = col; k < n; ++k) a[r][k] -= f * a[col][k];
      b[r] -= f * b[col];
    }
  }
  std::vector<double> x(n);
  for (size_t r = n; r-- > 0;) {
    double sum = b[r];
    for (size_t k = r + 1; k < n; ++k) sum -= a[r][k] * x[k];
    x[r] = sum / a[r][r];
  }
  return x;
}

TEST(LargeSteps, MatchesADenseSolve) {
  const uint32_t n = 5;
  const std::vector<glm::uvec3> triangles = gridTriangles(n);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::vector<double> b(n * n);
  for (double& v : b) v = normal(rng);
  for (double lambda : {0.1, 3.0, 100.0}) {
    std::vector<double> x = b;
    solveLargeSteps(triangles, b.size(), lambda, x);
    const std::vector<double> expected = denseSolve(triangles, b.size(), lambda, b);
    for (size_t i = 0; i < b.size(); ++i) EXPECT_NEAR(x[i], expected[i], 1e-8) << "lambda " << lambda << " vertex " << i;
  }
}

double norm(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x * x;
  return std::sqrt(sum);
}

TEST(LargeSteps, IsASmoothingOperator) {
  const uint32_t n = 8;
  const std::vector<glm::uvec3> triangles = gridTriangles(n);
  const double lambda = 2.0;
  // Constants pass unchanged (L 1 = 0) and the sum is kept (1^T L = 0).
  std::vector<double> constant(n * n, 3.0);
  solveLargeSteps(triangles, constant.size(), lambda, constant);
  for (double v : constant) EXPECT_NEAR(v, 3.0, 1e-9);
  // A smooth ramp is damped far less than a checkerboard of the same norm.
  std::vector<double> ramp(n * n), checker(n * n);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      ramp[j * n + i] = double(i) - 3.5;
      checker[j * n + i] = ((i + j) % 2 ? 1.0 : -1.0) * norm(ramp) / n;
    }
  double rampSum = 0;
  for (double v : ramp) rampSum += v;
  std::vector<double> smoothRamp = ramp, smoothChecker = checker;
  solveLargeSteps(triangles, ramp.size(), lambda, smoothRamp);
  solveLargeSteps(triangles, checker.size(), lambda, smoothChecker);
  double smoothSum = 0;
  for (double v : smoothRamp) smoothSum += v;
  EXPECT_NEAR(smoothSum, rampSum, 1e-9);
  EXPECT_LE(norm(smoothRamp), norm(ramp));
  EXPECT_LE(norm(smoothChecker), norm(checker));
  EXPECT_LT(norm(smoothChecker) / norm(checker), 0.5 * norm(smoothRamp) / norm(ramp));
}

TEST(LargeSteps, ZeroLambdaAndZeroRightHandSideAndErrors) {
  const std::vector<glm::uvec3> triangles = gridTriangles(3);
  std::vector<double> b = {1, -2, 3, 4, 5, 6, 7, 8, 9};
  const std::vector<double> original = b;
  solveLargeSteps(triangles, 9, 0.0, b);
  for (size_t i = 0; i < b.size(); ++i) EXPECT_NEAR(b[i], original[i], 1e-12);
  std::vector<double> zero(9, 0.0);
  solveLargeSteps(triangles, 9, 5.0, zero);
  EXPECT_EQ(zero, std::vector<double>(9, 0.0));
  expectError([&] { solveLargeSteps(triangles, 10, 1.0, b); }, {"9 entries for 10 vertices"});
  expectError([&] { solveLargeSteps(triangles, 9, -1.0, b); }, {"lambda"});
  expectError([&] { solveLargeSteps(triangles, 4, 1.0, std::span<double>(b).first(4)); }, {"names vertex"});
}

TEST(ExperimentRegularization, GradientInThetaMatchesFiniteDifferences) {
  const Experiment x = loadExperiment(kData / "complete.json");  // heights h0-h15, grey, t0
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> uniform(-0.2, 0.2);
  std::vector<double> theta(x.parameters.size());
  for (double& t : theta) t = uniform(rng);
  std::vector<double> gradient(theta.size(), 0.5);
  const double energy = regularization(x, theta, gradient);
  EXPECT_GT(energy, 0);
  EXPECT_EQ(gradient[16], 0.5);  // albedo and gate centre do not move vertices
  EXPECT_EQ(gradient[17], 0.5);
  const double h = 1e-6;
  for (size_t k = 0; k < 16; ++k) {
    std::vector<double> plus = theta, minus = theta, unused(theta.size(), 0.0);
    plus[k] += h;
    minus[k] -= h;
    const double fd = (regularization(x, plus, unused) - regularization(x, minus, unused)) / (2 * h);
    EXPECT_NEAR(gradient[k] - 0.5, fd, 1e-8) << x.parameters[k].name;
  }
  // The energy is the Laplacian energy of the heightfield displaced by θ along +y.
  std::vector<glm::dvec3> positions(x.scene.shapes[0].positions.begin(), x.scene.shapes[0].positions.end());
  for (size_t k = 0; k < 16; ++k) positions[k].y += theta[k];
  EXPECT_NEAR(energy, energyOf(positions, x.scene.shapes[0].triangles, 0.1), 1e-15);
}

TEST(ExperimentPreconditioner, SmoothsTheShapesEntriesOnly) {
  const Experiment x = loadExperiment(kData / "complete.json");
  std::vector<double> gradient(x.parameters.size());
  for (size_t i = 0; i < gradient.size(); ++i) gradient[i] = std::sin(double(i) * 1.3);
  std::vector<double> expected(gradient.begin(), gradient.begin() + 16);
  solveLargeSteps(x.scene.shapes[0].triangles, 16, 4.0, expected);
  std::vector<double> preconditioned = gradient;
  preconditionGradient(x, preconditioned);
  for (size_t k = 0; k < 16; ++k) EXPECT_NEAR(preconditioned[k], expected[k], 1e-12);
  EXPECT_EQ(preconditioned[16], gradient[16]);
  EXPECT_EQ(preconditioned[17], gradient[17]);
  expectError([&] {
    std::vector<double> wrong(3);
    preconditionGradient(x, wrong);
  }, {"3 values for 18 parameters"});
}

// Free vertex positions (a vertex_positions entry: x, y and z parameters per vertex): the
// preconditioner smooths each direction's entries as a field of its own, which is (I + λ L)⁻¹
// applied to the xyz gradient field. Heights and coordinates of one vertex together are refused:
// h5 and v5_y move vertex 5 along one direction.
TEST(FreeVertexPositions, PreconditionerSmoothsEachDirectionApart) {
  const nlohmann::json experiment = {
      {"version", 1},
      {"scene", "terrain_free.json"},
      {"parameters", {{{"name", "v*"}}, {{"name", "grey"}}}},
      {"targets", {{{"image", "front.exr"}}}},
      {"preconditioner", {{"type", "large_steps"}, {"shape", "terrain"}, {"lambda", 3}}}};
  const Experiment x = parseExperimentJson(experiment.dump(), "free.experiment.json", kData);
  ASSERT_EQ(x.parameters.size(), 49u);
  std::vector<double> gradient(x.parameters.size());
  for (size_t i = 0; i < gradient.size(); ++i) gradient[i] = std::cos(double(i) * 0.7);
  std::vector<double> preconditioned = gradient;
  preconditionGradient(x, preconditioned);
  for (size_t axis = 0; axis < 3; ++axis) {
    std::vector<double> field(16);
    for (size_t v = 0; v < 16; ++v) field[v] = gradient[3 * v + axis];
    solveLargeSteps(x.scene.shapes[0].triangles, 16, 3.0, field);
    for (size_t v = 0; v < 16; ++v) EXPECT_NEAR(preconditioned[3 * v + axis], field[v], 1e-12) << x.parameters[3 * v + axis].name;
  }
  EXPECT_EQ(preconditioned[48], gradient[48]);
  nlohmann::json both = experiment;
  both["parameters"].push_back({{"name", "h5"}});
  expectError([&] { parseExperimentJson(both.dump(), "free.experiment.json", kData); },
              {"preconditioner.shape", "displaced by both \"v5_y\" and \"h5\" along one direction"});
}

}  // namespace
}  // namespace vktg
