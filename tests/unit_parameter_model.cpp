// ParameterModel: the scene at a parameter vector θ is the scene applyParameters makes; the device's
// per-vertex op lists keep declaration order; and the chain rule from scene-quantity gradients to
// dℓ/dθ is the derivative of the scene's motion at θ (not only at θ = 0), checked by central
// differences of a linear functional of the scene.
#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vktg/error.h"
#include "vktg/parameter_model.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

// Two parameters of different kinds on one shape (they do not commute), a heightfield, a light and
// every scalar kind.
Scene modelScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1, 4], "look_at": [0, 0.5, 0], "resolution": [8, 8]},
    "gate": {"type": "box", "a": 1, "b": 5},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5},
                  "glass": {"type": "dielectric", "roughness": 0.3, "ior": 1.5}},
    "shapes": [
      {"name": "lamp", "type": "rectangle", "material": "m", "emission": 1,
       "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0], "scale": 0.25}},
      {"name": "prism", "type": "cube", "material": "glass",
       "transform": {"translate": [-0.5, 0.3, 0.2], "rotate": [0, 30, 0], "scale": 0.2}},
      {"name": "ground", "type": "heightfield", "resolution": [3, 3], "size": [2, 2],
       "heights": [0, 0.1, 0, 0.2, 0.3, 0.1, 0, 0.05, 0], "material": "m",
       "transform": {"rotate": [10, 20, 0], "scale": [1, 1.5, 1]}}
    ],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 1], "intensity": 2}],
    "parameters": [
      {"name": "slide", "type": "translate", "shape": "prism", "axis": [1, 0, 0]},
      {"name": "spin", "type": "rotate", "shape": "prism", "axis": [0, 1, 0], "center": [1, 0, 0]},
      {"name": "lift", "type": "displace", "shape": "prism", "vertices": [0, 3], "direction": [0, 0, 1]},
      {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
      {"name": "laser_y", "type": "light_position", "light": "laser", "axis": [0, 1, 0]},
      {"name": "glow", "type": "emission", "shape": "lamp"},
      {"name": "power", "type": "intensity", "light": "laser"},
      {"name": "grey", "type": "albedo", "material": "m"},
      {"name": "eta", "type": "ior", "material": "glass"},
      {"name": "t0", "type": "gate_center"}
    ]
  })", "model.json", ".");
}

std::vector<uint32_t> allParameters(const Scene& scene) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < scene.parameters.size(); ++i) out.push_back(i);
  return out;
}

// F(scene) = sum of g . (every quantity g has an entry for).
double functional(const Scene& s, const SceneGradient& g) {
  double f = 0;
  size_t v = 0;
  for (const Shape& shape : s.shapes)
    for (const glm::vec3& p : shape.positions) f += glm::dot(g.vertices[v++], glm::dvec3(p));
  for (size_t m = 0; m < s.materials.size(); ++m)
    f += glm::dot(g.materials[m], glm::dvec3(s.materials[m].albedo, s.materials[m].roughness, s.materials[m].ior));
  for (size_t i = 0; i < s.shapes.size(); ++i) f += g.emission[i] * s.shapes[i].emission;
  for (size_t l = 0; l < s.pointLights.size(); ++l)
    f += g.intensity[l] * s.pointLights[l].intensity + glm::dot(g.lightPosition[l], glm::dvec3(s.pointLights[l].position));
  return f + g.gateCenter * s.gate.a;
}

TEST(ParameterModel, SceneAtMatchesApplyParameters) {
  const Scene scene = modelScene();
  // θ in reverse declaration order: the model applies them in declaration order regardless.
  std::vector<uint32_t> selected = allParameters(scene);
  std::reverse(selected.begin(), selected.end());
  ParameterModel model(scene, selected);
  std::vector<double> theta(model.size());
  std::vector<std::pair<uint32_t, double>> values;
  for (size_t k = 0; k < theta.size(); ++k) {
    theta[k] = 0.01 * double(k % 7 + 1);
    values.emplace_back(selected[k], theta[k]);
  }
  const Scene expected = applyParameters(scene, values);
  const Scene got = model.sceneAt(theta);
  for (size_t s = 0; s < scene.shapes.size(); ++s) {
    EXPECT_EQ(got.shapes[s].positions, expected.shapes[s].positions) << scene.shapes[s].name;
    const std::vector<glm::dvec3> positions = model.shapePositions(theta, uint32_t(s));
    for (size_t i = 0; i < positions.size(); ++i)
      EXPECT_EQ(glm::vec3(positions[i]), expected.shapes[s].positions[i]) << scene.shapes[s].name << " vertex " << i;
  }
  EXPECT_EQ(got.materials[0].albedo, expected.materials[0].albedo);
  EXPECT_EQ(got.gate.a, expected.gate.a);
  EXPECT_EQ(got.pointLights[0].position, expected.pointLights[0].position);
}

TEST(ParameterModel, VertexOpsFollowDeclarationOrder) {
  const Scene scene = modelScene();
  // Select spin before slide: θ order differs from declaration order.
  const uint32_t slide = findParameter(scene, "slide"), spin = findParameter(scene, "spin"),
                 lift = findParameter(scene, "lift"), h4 = findParameter(scene, "h4");
  ParameterModel model(scene, {lift, spin, slide, h4});
  const VertexOpTables t = model.deviceTables();
  const uint32_t prismFirst = uint32_t(scene.shapes[0].positions.size());
  // Vertex 0 of the prism: slide (θ index 2), spin (1), lift (0), in the order the scene declares them.
  const glm::uvec2 ops = t.vertexOps[prismFirst + 0];
  ASSERT_EQ(ops.y, 3u);
  EXPECT_EQ(t.opList[ops.x + 0], 2u);
  EXPECT_EQ(t.opList[ops.x + 1], 1u);
  EXPECT_EQ(t.opList[ops.x + 2], 0u);
  EXPECT_EQ(t.vertexOps[prismFirst + 1].y, 2u);  // not lifted
  const uint32_t groundFirst = prismFirst + uint32_t(scene.shapes[1].positions.size());
  EXPECT_EQ(t.vertexOps[groundFirst + 4].y, 1u);
  EXPECT_EQ(t.vertexOps[groundFirst + 3].y, 0u);
  EXPECT_TRUE(model.movingVertices()[groundFirst + 4]);
  EXPECT_FALSE(model.movingVertices()[groundFirst + 3]);
  EXPECT_FALSE(model.movingVertices()[0]);  // the lamp
  EXPECT_EQ(t.parameterOps.size(), 4u);
  EXPECT_EQ(std::bit_cast<uint32_t>(t.parameterOps[1].axisKind.w), uint32_t(ParameterKind::Rotate));
}

// What a selection touches is known from construction; each answer follows its own kinds only.
TEST(ParameterModel, WhatASelectionTouchesAndWhichVerticesDeform) {
  const Scene scene = modelScene();
  auto model = [&](const std::vector<std::string>& names) {
    std::vector<uint32_t> selected;
    for (const std::string& n : names) selected.push_back(findParameter(scene, n));
    return ParameterModel(scene, selected);
  };
  const ParameterModel scalars = model({"glow", "power", "grey", "t0"});
  EXPECT_TRUE(scalars.touchesEmission() && scalars.touchesIntensity() && scalars.touchesMaterials() && scalars.touchesGate());
  EXPECT_FALSE(scalars.movesPointLights() || scalars.movesVertices());
  EXPECT_TRUE(model({"eta"}).touchesMaterials());
  EXPECT_FALSE(model({"eta"}).touchesEmission() || model({"eta"}).touchesGate());
  EXPECT_TRUE(model({"laser_y"}).movesPointLights());
  EXPECT_FALSE(model({"laser_y"}).touchesIntensity());
  // lift displaces prism vertices 0 and 3 (the lamp's 4 vertices come first); slide moves the
  // prism rigidly; h4 displaces the ground's centre vertex.
  const ParameterModel moving = model({"slide", "lift", "h4"});
  const std::vector<bool>& deforming = moving.deformingVertices();
  const std::vector<bool>& movingVertex = moving.movingVertices();
  const size_t prism = 4, ground = 4 + scene.shapes[1].positions.size();
  ASSERT_EQ(deforming.size(), ground + 9);
  for (size_t v = 0; v < deforming.size(); ++v) {
    const bool displaced = v == prism || v == prism + 3 || v == ground + 4;
    EXPECT_EQ(deforming[v], displaced) << "vertex " << v;
    EXPECT_EQ(movingVertex[v], displaced || (v >= prism && v < ground)) << "vertex " << v;
  }
}

// The world axes an adjoint gradient accumulates per vertex (host/adjoint.cpp): a translation's
// nonzero components, a displacement's direction, all three once a rotation is selected.
TEST(ParameterModel, VertexMotionAxesAreTheComponentsParametersMoveAlong) {
  const Scene scene = modelScene();
  auto axes = [](const Scene& s, const std::vector<std::string>& names) {
    std::vector<uint32_t> selected;
    for (const std::string& n : names) selected.push_back(findParameter(s, n));
    return ParameterModel(s, selected).vertexMotionAxes();
  };
  EXPECT_EQ(axes(scene, {"slide"}), glm::bvec3(true, false, false));
  EXPECT_EQ(axes(scene, {"slide", "spin"}), glm::bvec3(true));
  EXPECT_EQ(axes(scene, {"grey", "laser_y", "t0"}), glm::bvec3(false));
  // The ground's transform tilts its height axis: every component moves.
  EXPECT_EQ(axes(scene, {"h4"}), glm::bvec3(true));
  const Scene flat = parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1, 4], "look_at": [0, 0, 0], "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"name": "ground", "type": "heightfield", "resolution": [2, 2], "size": [2, 2],
                "heights": [0, 0.1, 0.2, 0], "material": "m"}],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 1], "intensity": 2}],
    "parameters": [{"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
                   {"name": "side", "type": "translate", "shape": "ground", "axis": [0, 0, 1]}]
  })", "flat.json", ".");
  EXPECT_EQ(axes(flat, {"h0", "h3"}), glm::bvec3(false, true, false));
  EXPECT_EQ(axes(flat, {"h0", "side"}), glm::bvec3(false, true, true));
}

// The chain rule at a θ far from 0, where the translation's velocity is turned by the rotation
// applied after it. Tolerance: central differences with step 1e-3 in float-rounded positions
// (relative rounding 6e-8 of coordinates ~1, divided by 2e-3) plus the O(eps^2) curvature of the
// rotation, both far below 1e-3 of the derivative's scale.
TEST(ParameterModel, ChainRuleIsTheDerivativeAtTheta) {
  const Scene scene = modelScene();
  ParameterModel model(scene, allParameters(scene));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SceneGradient g;
  g.resize(scene);
  for (glm::dvec3& v : g.vertices) v = glm::dvec3(u(rng), u(rng), u(rng));
  for (glm::dvec3& m : g.materials) m = glm::dvec3(u(rng), u(rng), u(rng));
  for (double& e : g.emission) e = u(rng);
  for (double& i : g.intensity) i = u(rng);
  for (glm::dvec3& p : g.lightPosition) p = glm::dvec3(u(rng), u(rng), u(rng));
  g.gateCenter = u(rng);

  std::vector<double> theta(model.size());
  for (size_t k = 0; k < theta.size(); ++k) theta[k] = 0.05 * u(rng);
  theta[findParameter(scene, "spin")] = 0.7;  // selected in scene order: θ index = scene index
  const std::vector<double> gradient = model.chainRule(theta, g);
  const double eps = 1e-3;
  for (size_t k = 0; k < model.size(); ++k) {
    std::vector<double> plus = theta, minus = theta;
    plus[k] += eps;
    minus[k] -= eps;
    const double fd = (functional(model.sceneAt(plus), g) - functional(model.sceneAt(minus), g)) / (2 * eps);
    EXPECT_NEAR(gradient[k], fd, 1e-3 * (1.0 + std::abs(fd))) << model.parameter(k).name;
  }
}

// The loss gradient's form, vertices in fixed point as its accumulators hold them (only the
// components along the axes the selected parameters move vertices along): the same numbers bit for
// bit as converting them to doubles first and applying the chain rule to those.
TEST(ParameterModel, ChainRuleOfFixedPointVerticesEqualsTheirConversion) {
  const Scene scene = modelScene();
  // All three axes (the rotation), x alone, and x and z (the displacement's rotated direction).
  const std::vector<std::pair<std::vector<std::string>, uint32_t>> selections{
      {{}, 3}, {{"slide", "grey", "t0"}, 1}, {{"slide", "lift"}, 2}};
  for (const auto& [names, expectedStride] : selections) {
    std::vector<uint32_t> selected;
    for (const std::string& n : names) selected.push_back(findParameter(scene, n));
    ParameterModel model(scene, names.empty() ? allParameters(scene) : selected);
    const glm::bvec3 axes = model.vertexMotionAxes();
    const uint32_t stride = model.vertexGradientStride();
    ASSERT_EQ(stride, expectedStride);
    std::mt19937_64 rng(5);
    const double scale = std::ldexp(1.0, 40);
    SceneGradient g;
    g.resize(scene);
    std::vector<int64_t> fixed(stride * g.vertices.size());
    for (int64_t& f : fixed) f = int64_t(rng() >> 20) - (int64_t(1) << 43);
    for (uint32_t i = 0; i < stride; ++i) fixed[stride + i] = 0;  // a vertex no sample touched
    for (size_t v = 0; v < g.vertices.size(); ++v) {
      const int64_t* f = fixed.data() + stride * v;
      for (int axis = 0; axis < 3; ++axis) g.vertices[v][axis] = axes[axis] ? double(*f++) / scale : 0.0;
    }
    g.materials.assign(g.materials.size(), glm::dvec3(0.25, -0.5, 0.125));
    g.gateCenter = 0.375;
    std::vector<double> theta(model.size(), 0.0);
    for (size_t k = 0; k < model.size(); ++k)
      if (model.parameter(k).name == "spin") theta[k] = 0.7;
    const std::vector<double> converted = model.chainRule(theta, g);
    SceneGradient scalars = g;
    scalars.vertices.clear();
    const std::vector<double> direct = model.chainRule(theta, scalars, fixed, scale);
    ASSERT_EQ(direct.size(), converted.size());
    for (size_t k = 0; k < direct.size(); ++k) EXPECT_EQ(direct[k], converted[k]) << model.parameter(k).name;
    EXPECT_THROW(model.chainRule(theta, scalars, std::span<const int64_t>(fixed).first(fixed.size() - stride), scale),
                 Error);
  }
}

}  // namespace
}  // namespace vktg
