// Scene parameters: the velocity fields bindParameters hands to the renderer must be the derivative
// of the motion perturbScene applies (central differences, float precision); every scalar kind
// changes its one scalar and nothing else; gate shifts move every gate type; bad parameter blocks and
// command-line selections fail with file, field and problem.
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/table_case_name.h"
#include "vktg/error.h"
#include "vktg/parameters.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kScenes = fs::path(VKTG_SOURCE_DIR) / "scenes";
const char* kFile = "params.json";

// Every parameter kind, on shapes placed off the origin and turned, so that centres, axes and
// transforms all matter.
json baseScene() {
  return json::parse(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1, 4], "look_at": [0, 0.5, 0], "resolution": [8, 8]},
    "gate": {"type": "box", "a": 1, "b": 5},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5},
                  "metal": {"type": "conductor", "albedo": 0.5, "roughness": 0.3},
                  "glass": {"type": "dielectric", "roughness": 0.3, "ior": 1.5},
                  "unused": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"name": "lamp", "type": "rectangle", "material": "m", "emission": 1,
       "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0], "scale": 0.25}},
      {"name": "ball", "type": "sphere", "subdivisions": 1, "material": "metal",
       "transform": {"translate": [0.5, 0.5, 0], "scale": 0.3}},
      {"name": "prism", "type": "cube", "material": "glass",
       "transform": {"translate": [-0.5, 0.3, 0.2], "rotate": [0, 30, 0], "scale": 0.2}},
      {"name": "ground", "type": "heightfield", "resolution": [3, 3], "size": [2, 2],
       "heights": [0, 0.1, 0, 0.2, 0.3, 0.1, 0, 0.05, 0], "material": "m",
       "transform": {"translate": [0, -0.1, 0], "rotate": [10, 20, 0], "scale": [1, 1.5, 1]}}
    ],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 1], "intensity": 2}],
    "parameters": [
      {"name": "ball_x", "type": "translate", "shape": "ball", "axis": [1, 1, 0]},
      {"name": "prism_spin", "type": "rotate", "shape": "prism", "axis": [0.2, 1, 0.1], "center": [1, 2, -3]},
      {"name": "prism_tilt", "type": "rotate", "shape": "prism", "axis": [1, 0, 0]},
      {"name": "bump", "type": "displace", "shape": "ground", "vertices": [4, 1], "direction": [0, 2, 0]},
      {"name": "lift", "type": "displace", "shape": "ball", "vertices": "all", "direction": [0, 0, 1]},
      {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
      {"name": "laser_y", "type": "light_position", "light": "laser", "axis": [0, 1, 0]},
      {"name": "glow", "type": "emission", "shape": "lamp"},
      {"name": "power", "type": "intensity", "light": "laser"},
      {"name": "grey", "type": "albedo", "material": "m"},
      {"name": "shine", "type": "roughness", "material": "metal"},
      {"name": "frost", "type": "roughness", "material": "glass"},
      {"name": "eta", "type": "ior", "material": "glass"},
      {"name": "t0", "type": "gate_center"}
    ]
  })");
}

Scene parse(const json& j) { return parseSceneJson(j.dump(), kFile, kScenes); }

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::vector<glm::vec3> allVertices(const Scene& scene) {
  std::vector<glm::vec3> out;
  for (const Shape& s : scene.shapes) out.insert(out.end(), s.positions.begin(), s.positions.end());
  return out;
}

// The first difference between two scenes, or "" if none (exact comparison: a perturbation must
// leave everything but its target bit for bit as it was).
std::string differenceBetween(const Scene& a, const Scene& b) {
  if (a.materials.size() != b.materials.size()) return "material count";
  for (size_t i = 0; i < a.materials.size(); ++i) {
    const Material &x = a.materials[i], &y = b.materials[i];
    if (x.name != y.name || x.type != y.type || x.albedo != y.albedo || x.roughness != y.roughness || x.ior != y.ior)
      return "material " + x.name;
  }
  if (a.shapes.size() != b.shapes.size()) return "shape count";
  for (size_t i = 0; i < a.shapes.size(); ++i) {
    const Shape &x = a.shapes[i], &y = b.shapes[i];
    if (x.name != y.name || x.positions != y.positions || x.triangles != y.triangles || x.material != y.material ||
        x.emission != y.emission)
      return "shape " + x.name;
  }
  if (a.pointLights.size() != b.pointLights.size()) return "light count";
  for (size_t i = 0; i < a.pointLights.size(); ++i) {
    const PointLight &x = a.pointLights[i], &y = b.pointLights[i];
    if (x.name != y.name || x.position != y.position || x.intensity != y.intensity) return "light " + x.name;
  }
  const Gate &g = a.gate, &h = b.gate;
  if (g.type != h.type || g.mu != h.mu || g.sigma != h.sigma || g.a != h.a || g.b != h.b || g.binStart != h.binStart ||
      g.binWidth != h.binWidth || g.binCount != h.binCount || g.normalize != h.normalize)
    return "gate";
  if (a.camera.position != b.camera.position || a.camera.lookAt != b.camera.lookAt) return "camera";
  if (a.parameters.size() != b.parameters.size()) return "parameter count";
  return "";
}

const Parameter& parameterNamed(const Scene& scene, const std::string& name) {
  return scene.parameters[findParameter(scene, name)];
}

TEST(Parameters, BaseSceneParsesEveryKind) {
  const Scene scene = parse(baseScene());
  ASSERT_EQ(scene.parameters.size(), 13u + 9u);  // 13 named + one per vertex of the 3x3 heightfield
  EXPECT_EQ(parameterNamed(scene, "ball_x").kind, ParameterKind::Translate);
  EXPECT_LT(glm::distance(parameterNamed(scene, "ball_x").axis, glm::normalize(glm::vec3(1, 1, 0))), 1e-7f);
  EXPECT_EQ(parameterNamed(scene, "prism_spin").center, glm::vec3(1, 2, -3));
  // Without `center` a rotation turns about the centre of the shape's bounds: the cube's translation.
  EXPECT_LT(glm::distance(parameterNamed(scene, "prism_tilt").center, glm::vec3(-0.5f, 0.3f, 0.2f)), 1e-6f);
  EXPECT_EQ(parameterNamed(scene, "bump").vertices, (std::vector<uint32_t>{4, 1}));
  EXPECT_EQ(parameterNamed(scene, "bump").axis, glm::vec3(0, 1, 0));  // direction normalised
  EXPECT_EQ(parameterNamed(scene, "lift").vertices.size(), scene.shapes[1].positions.size());
  for (uint32_t k = 0; k < 9; ++k) {
    const Parameter& h = parameterNamed(scene, "h" + std::to_string(k));
    EXPECT_EQ(h.kind, ParameterKind::Displace);
    EXPECT_EQ(h.target, "ground");
    EXPECT_EQ(h.vertices, std::vector<uint32_t>{k});
  }
  EXPECT_EQ(parameterNamed(scene, "laser_y").kind, ParameterKind::LightPosition);
  EXPECT_EQ(parameterNamed(scene, "t0").kind, ParameterKind::GateCenter);
  EXPECT_EQ(parameterNamed(scene, "eta").target, "glass");
}

TEST(Parameters, KindClassification) {
  const ParameterKind geometric[] = {ParameterKind::Translate, ParameterKind::Rotate, ParameterKind::Displace,
                                     ParameterKind::LightPosition};
  const ParameterKind scalar[] = {ParameterKind::Emission, ParameterKind::Intensity, ParameterKind::Albedo,
                                  ParameterKind::Roughness, ParameterKind::Ior, ParameterKind::GateCenter};
  for (ParameterKind k : geometric) EXPECT_TRUE(isGeometric(k)) << parameterKindName(k);
  for (ParameterKind k : scalar) EXPECT_FALSE(isGeometric(k)) << parameterKindName(k);
  EXPECT_FALSE(movesVertices(ParameterKind::LightPosition));
  std::set<std::string> names;
  for (ParameterKind k : geometric) names.insert(parameterKindName(k));
  for (ParameterKind k : scalar) names.insert(parameterKindName(k));
  EXPECT_EQ(names.size(), 10u);
}

// The core contract: (V(+eps) - V(-eps)) / 2 eps = dV/dtheta at every vertex of the scene. The
// tolerance is what float storage allows: each perturbed coordinate is rounded once (half an ulp of
// the largest coordinate on either side), the velocity is stored as a float, and a rotation's
// central difference carries the third-order term |v| eps^2 / 6.
TEST(Parameters, VelocityFieldsAreTheDerivativeOfThePerturbation) {
  const Scene scene = parse(baseScene());
  const std::vector<glm::vec3> base = allVertices(scene);
  std::vector<std::string> names = {"ball_x", "prism_spin", "prism_tilt", "bump", "lift"};
  for (int k = 0; k < 9; ++k) names.push_back("h" + std::to_string(k));
  const std::vector<ParameterBinding> bindings = bindParameters(scene, names);
  ASSERT_EQ(bindings.size(), names.size());
  constexpr double kEps = 1e-3;
  const double ulp = std::ldexp(1.0, -23);
  for (const ParameterBinding& b : bindings) {
    SCOPED_TRACE(b.name);
    ASSERT_EQ(b.vertexVelocity.size(), base.size());
    const std::vector<glm::vec3> plus = allVertices(perturbScene(scene, b.name, kEps));
    const std::vector<glm::vec3> minus = allVertices(perturbScene(scene, b.name, -kEps));
    size_t moving = 0;
    for (size_t i = 0; i < base.size(); ++i) {
      const glm::dvec3 v(b.vertexVelocity[i]);
      if (v == glm::dvec3(0)) {
        // Not moved by this parameter: unchanged bit for bit.
        EXPECT_EQ(plus[i], base[i]) << "vertex " << i;
        EXPECT_EQ(minus[i], base[i]) << "vertex " << i;
        continue;
      }
      ++moving;
      const glm::dvec3 difference = (glm::dvec3(plus[i]) - glm::dvec3(minus[i])) / (2 * kEps);
      for (int c = 0; c < 3; ++c) {
        const double scale = std::max(std::abs(plus[i][c]), std::abs(minus[i][c]));
        const double tolerance =
            ulp * scale / (2 * kEps) + ulp * glm::length(v) + glm::length(v) * kEps * kEps / 6 + 1e-12;
        EXPECT_NEAR(difference[c], v[c], tolerance) << "vertex " << i << " component " << c;
      }
    }
    EXPECT_GT(moving, 0u);
  }
}

// Independent checks of the fields' shape: a translation is the unit axis everywhere on its shape,
// a rotation is perpendicular to its axis with speed = distance from the axis, a displacement
// touches exactly its vertices, and a height parameter only its own vertex.
TEST(Parameters, VelocityFieldsHaveTheExpectedForm) {
  const Scene scene = parse(baseScene());
  const std::vector<glm::vec3> base = allVertices(scene);
  const size_t ballFirst = scene.shapes[0].positions.size();
  const size_t prismFirst = ballFirst + scene.shapes[1].positions.size();
  const size_t groundFirst = prismFirst + scene.shapes[2].positions.size();

  const auto b = bindParameters(scene, {"ball_x", "prism_spin", "bump", "h5", "laser_y"});
  EXPECT_EQ(b[0].target, 1u);
  for (size_t i = 0; i < base.size(); ++i) {
    const bool onBall = i >= ballFirst && i < prismFirst;
    EXPECT_EQ(b[0].vertexVelocity[i], onBall ? glm::normalize(glm::vec3(1, 1, 0)) : glm::vec3(0)) << i;
  }
  const glm::vec3 axis = glm::normalize(glm::vec3(0.2f, 1, 0.1f)), center(1, 2, -3);
  for (size_t i = prismFirst; i < groundFirst; ++i) {
    const glm::vec3 v = b[1].vertexVelocity[i];
    const glm::vec3 r = base[i] - center;
    EXPECT_NEAR(glm::dot(v, axis), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(v), glm::length(r - axis * glm::dot(r, axis)), 1e-5f);
    EXPECT_NEAR(glm::dot(v, r), 0.0f, 1e-5f);
  }
  for (size_t i = 0; i < base.size(); ++i) {
    const bool bumped = i == groundFirst + 4 || i == groundFirst + 1;
    EXPECT_EQ(b[2].vertexVelocity[i], bumped ? glm::vec3(0, 1, 0) : glm::vec3(0)) << i;
    EXPECT_EQ(b[3].vertexVelocity[i] != glm::vec3(0), i == groundFirst + 5) << i;
  }
  EXPECT_EQ(b[2].target, 3u);
  EXPECT_TRUE(b[4].vertexVelocity.empty());
  EXPECT_EQ(b[4].lightVelocity, glm::vec3(0, 1, 0));
  EXPECT_EQ(b[4].target, 0u);
}

// h_k adds to heights[k] of the file: perturbing h_k by delta gives the scene whose file has
// heights[k] + delta, through the heightfield's rotation and non-uniform scale.
TEST(Parameters, HeightParametersEditTheFileHeights) {
  const json file = baseScene();
  const Scene scene = parse(file);
  constexpr double kDelta = 0.25;
  for (int k = 0; k < 9; ++k) {
    SCOPED_TRACE(k);
    json edited = file;
    edited["shapes"][3]["heights"][k] = edited["shapes"][3]["heights"][k].get<double>() + kDelta;
    const Scene expected = parse(edited);
    const Scene moved = perturbScene(scene, "h" + std::to_string(k), kDelta);
    const Shape &a = moved.shapes[3], &e = expected.shapes[3];
    for (size_t i = 0; i < a.positions.size(); ++i) EXPECT_LT(glm::distance(a.positions[i], e.positions[i]), 2e-6f) << i;
    // The moved vertex really moved, by the scaled height (scale y = 1.5).
    EXPECT_NEAR(glm::distance(a.positions[k], scene.shapes[3].positions[k]), 1.5 * kDelta, 1e-6);
  }
}

TEST(Parameters, LightPositionMovesOnlyTheLight) {
  const Scene scene = parse(baseScene());
  Scene moved = perturbScene(scene, "laser_y", 0.5);
  EXPECT_EQ(moved.pointLights[0].position, glm::vec3(0, 1.5f, 1));
  moved.pointLights[0].position = scene.pointLights[0].position;
  EXPECT_EQ(differenceBetween(moved, scene), "");
}

TEST(Parameters, GeometricPerturbationsTouchOnlyTheirShape) {
  const Scene scene = parse(baseScene());
  for (const std::string name : {"ball_x", "prism_spin", "bump", "h2"}) {
    SCOPED_TRACE(name);
    Scene moved = perturbScene(scene, name, 0.1);
    const uint32_t target = bindParameters(scene, {name})[0].target;
    EXPECT_NE(moved.shapes[target].positions, scene.shapes[target].positions);
    moved.shapes[target].positions = scene.shapes[target].positions;
    EXPECT_EQ(differenceBetween(moved, scene), "");
  }
  // Zero perturbation is the scene itself, bit for bit.
  for (const Parameter& p : scene.parameters) EXPECT_EQ(differenceBetween(perturbScene(scene, p.name, 0.0), scene), "") << p.name;
}

// Each scalar kind adds delta to its one scalar; restoring that scalar gives back the scene exactly.
TEST(Parameters, ScalarPerturbationsChangeExactlyTheirScalar) {
  const Scene scene = parse(baseScene());
  struct Case {
    std::string name;
    ParameterKind kind;
    uint32_t target;
    std::function<float&(Scene&)> scalar;
  };
  const std::vector<Case> cases = {
      {"glow", ParameterKind::Emission, 0, [](Scene& s) -> float& { return s.shapes[0].emission; }},
      {"power", ParameterKind::Intensity, 0, [](Scene& s) -> float& { return s.pointLights[0].intensity; }},
      {"grey", ParameterKind::Albedo, 1, [](Scene& s) -> float& { return s.materials[1].albedo; }},
      {"shine", ParameterKind::Roughness, 2, [](Scene& s) -> float& { return s.materials[2].roughness; }},
      {"frost", ParameterKind::Roughness, 0, [](Scene& s) -> float& { return s.materials[0].roughness; }},
      {"eta", ParameterKind::Ior, 0, [](Scene& s) -> float& { return s.materials[0].ior; }},
  };
  // Materials are read in name order: glass, m, metal, unused.
  ASSERT_EQ(scene.materials[0].name, "glass");
  ASSERT_EQ(scene.materials[1].name, "m");
  ASSERT_EQ(scene.materials[2].name, "metal");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Scene original = scene;  // a copy, so c.scalar may take a mutable reference
    for (double delta : {0.05, -0.05}) {
      Scene moved = perturbScene(scene, c.name, delta);
      EXPECT_EQ(c.scalar(moved), float(double(c.scalar(original)) + delta));
      c.scalar(moved) = c.scalar(original);
      EXPECT_EQ(differenceBetween(moved, scene), "");
    }
    const ParameterBinding b = bindParameters(scene, {c.name})[0];
    EXPECT_EQ(b.kind, c.kind);
    EXPECT_EQ(b.target, c.target);
    EXPECT_TRUE(b.vertexVelocity.empty());
    EXPECT_EQ(b.lightVelocity, glm::vec3(0));
  }
  // The binding's target index names the scalar's owner.
  EXPECT_EQ(scene.materials[bindParameters(scene, {"grey"})[0].target].name, "m");
  EXPECT_EQ(scene.materials[bindParameters(scene, {"shine"})[0].target].name, "metal");
  EXPECT_EQ(scene.materials[bindParameters(scene, {"eta"})[0].target].name, "glass");
  EXPECT_EQ(scene.shapes[bindParameters(scene, {"glow"})[0].target].name, "lamp");
  EXPECT_EQ(scene.pointLights[bindParameters(scene, {"power"})[0].target].name, "laser");
}

// gate_center: W_theta(L) = W(L - theta) for every gate type, through the fields each type has.
TEST(Parameters, GateCenterShiftsEveryGateType) {
  const json gates[] = {
      {{"type", "gaussian"}, {"mu", 3}, {"sigma", 0.2}},
      {{"type", "box"}, {"a", 2}, {"b", 4}},
      {{"type", "truncated_gaussian"}, {"mu", 3}, {"sigma", 0.5}, {"a", 2.5}, {"b", 3.8}},
      {{"type", "bins"}, {"start", 2}, {"width", 0.1}, {"count", 20}},
  };
  constexpr double kDelta = 0.3;
  for (const json& g : gates) {
    SCOPED_TRACE(g.dump());
    json file = baseScene();
    file["gate"] = g;
    const Scene scene = parse(file);
    Scene moved = perturbScene(scene, "t0", kDelta);
    const Gate &a = scene.gate, &m = moved.gate;
    switch (a.type) {
      case GateType::Gaussian: EXPECT_EQ(m.mu, a.mu + kDelta); break;
      case GateType::Box:
        EXPECT_EQ(m.a, a.a + kDelta);
        EXPECT_EQ(m.b, a.b + kDelta);
        break;
      case GateType::TruncatedGaussian:
        EXPECT_EQ(m.mu, a.mu + kDelta);
        EXPECT_EQ(m.a, a.a + kDelta);
        EXPECT_EQ(m.b, a.b + kDelta);
        EXPECT_EQ(m.sigma, a.sigma);
        break;
      case GateType::Bins:
        EXPECT_EQ(m.binStart, a.binStart + kDelta);
        EXPECT_EQ(m.binWidth, a.binWidth);
        break;
      case GateType::Steady: FAIL();
    }
    // Sample lengths away from the jumps, where rounding of L + delta cannot cross an edge.
    for (double length = 1.013; length < 6; length += 0.0271)
      for (uint32_t layer = 0; layer < a.layers(); ++layer)
        EXPECT_NEAR(m.weight(length + kDelta, layer), a.weight(length, layer), 1e-12) << length << " " << layer;
    // Everything else is untouched.
    moved.gate = scene.gate;
    EXPECT_EQ(differenceBetween(moved, scene), "");
  }
}

TEST(Parameters, PerturbationErrors) {
  const Scene scene = parse(baseScene());
  const std::string unknown = errorOf([&] { perturbScene(scene, "ball_y", 0.1); });
  EXPECT_NE(unknown.find(kFile), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown parameter \"ball_y\""), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("ball_x"), std::string::npos) << unknown;  // the close match

  // Moves that leave the range the renderer treats smoothly are refused, not silently clamped.
  for (const auto& [name, delta] : std::vector<std::pair<std::string, double>>{
           {"shine", -0.3}, {"shine", 0.8}, {"grey", 0.6}, {"grey", -0.6}, {"eta", -0.5}, {"glow", -1.0},
           {"power", -2.5}, {"t0", -1.5}}) {
    const std::string message = errorOf([&] { perturbScene(scene, name, delta); });
    EXPECT_NE(message.find(kFile), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_NE(message.find("smaller step"), std::string::npos) << message;
  }
  EXPECT_NE(errorOf([&] { perturbScene(scene, "ball_x", std::nan("")); }).find("not finite"), std::string::npos);
  EXPECT_NE(errorOf([&] { bindParameters(scene, {"ball_x", "nope"}); }).find("unknown parameter \"nope\""),
            std::string::npos);
}

TEST(Parameters, SelectionByListAndWildcard) {
  const Scene scene = parse(baseScene());
  EXPECT_EQ(selectParameters(scene, "glow,ball_x"), (std::vector<std::string>{"glow", "ball_x"}));
  EXPECT_EQ(selectParameters(scene, " glow , ball_x "), (std::vector<std::string>{"glow", "ball_x"}));
  std::vector<std::string> heights;
  for (int k = 0; k < 9; ++k) heights.push_back("h" + std::to_string(k));
  EXPECT_EQ(selectParameters(scene, "h*"), heights);
  EXPECT_EQ(selectParameters(scene, "h3*"), std::vector<std::string>{"h3"});
  EXPECT_EQ(selectParameters(scene, "prism_*"), (std::vector<std::string>{"prism_spin", "prism_tilt"}));
  EXPECT_EQ(selectParameters(scene, "*_x"), std::vector<std::string>{"ball_x"});
  // Each name once, in the order first named.
  std::vector<std::string> mixed = {"t0"};
  mixed.insert(mixed.end(), heights.begin(), heights.end());
  EXPECT_EQ(selectParameters(scene, "t0,h*,h4,t0"), mixed);

  const std::string typo = errorOf([&] { selectParameters(scene, "glow,prism_spn"); });
  EXPECT_NE(typo.find(kFile), std::string::npos) << typo;
  EXPECT_NE(typo.find("--param:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("unknown parameter \"prism_spn\""), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean: prism_spin"), std::string::npos) << typo;
  const std::string far = errorOf([&] { selectParameters(scene, "zzzzzzzz"); });
  EXPECT_NE(far.find("the scene defines: ball_x"), std::string::npos) << far;
  EXPECT_NE(errorOf([&] { selectParameters(scene, "q*"); }).find("matches no parameter"), std::string::npos);
  EXPECT_NE(errorOf([&] { selectParameters(scene, "glow,,t0"); }).find("empty name"), std::string::npos);
  EXPECT_NE(errorOf([&] { selectParameters(scene, ""); }).find("--param"), std::string::npos);
  EXPECT_NE(errorOf([&] { selectParameters(scene, "glow,"); }).find("--param"), std::string::npos);
  EXPECT_NE(errorOf([&] { selectParameters(scene, "glo", "--grad-param"); }).find("--grad-param: "), std::string::npos);

  json bare = baseScene();
  bare.erase("parameters");
  const std::string none = errorOf([&] { selectParameters(parse(bare), "glow"); });
  EXPECT_NE(none.find("defines no parameters"), std::string::npos) << none;
}

struct BadCase {
  const char* name;
  std::function<void(json&)> edit;
  const char* field;
  const char* keyword;
};

// Index of a parameter in baseScene()'s block.
constexpr int kTranslate = 0, kRotate = 1, kDisplace = 3, kHeights = 5, kLight = 6, kEmission = 7, kIntensity = 8,
              kAlbedo = 9, kRoughness = 10, kIor = 12, kGate = 13;

json& param(json& j, int i) { return j["parameters"][i]; }

const BadCase kCases[] = {
    {"not an array", [](json& j) { j["parameters"] = json::object(); }, "parameters", "wrong type"},
    {"unknown type", [](json& j) { param(j, kTranslate)["type"] = "scale"; }, "parameters[0].type", "unknown type"},
    {"missing type", [](json& j) { param(j, kTranslate).erase("type"); }, "parameters[0].type", "missing required field"},
    {"unknown field", [](json& j) { param(j, kTranslate)["axes"] = {1, 0, 0}; }, "parameters[0].axes", "unknown field"},
    {"field of another type", [](json& j) { param(j, kTranslate)["center"] = {0, 0, 0}; }, "parameters[0].center", "unknown field"},
    {"missing name", [](json& j) { param(j, kEmission).erase("name"); }, "parameters[7].name", "missing required field"},
    {"name with a comma", [](json& j) { param(j, kEmission)["name"] = "a,b"; }, "parameters[7].name", "invalid parameter name"},
    {"name with a star", [](json& j) { param(j, kEmission)["name"] = "h*"; }, "parameters[7].name", "invalid parameter name"},
    {"duplicate name", [](json& j) { param(j, kEmission)["name"] = "ball_x"; }, "parameters[7].name", "duplicate parameter name \"ball_x\""},
    {"heights collide with a name", [](json& j) { param(j, kTranslate)["name"] = "h4"; }, "parameters[5].name_prefix", "duplicate parameter name \"h4\""},
    {"missing shape", [](json& j) { param(j, kTranslate).erase("shape"); }, "parameters[0].shape", "missing required field"},
    {"unknown shape", [](json& j) { param(j, kRotate)["shape"] = "prisma"; }, "parameters[1].shape", "unknown shape \"prisma\""},
    {"light is no shape", [](json& j) { param(j, kTranslate)["shape"] = "laser"; }, "parameters[0].shape", "unknown shape"},
    {"unknown light", [](json& j) { param(j, kLight)["light"] = "sun"; }, "parameters[6].light", "unknown light \"sun\""},
    {"unknown material", [](json& j) { param(j, kAlbedo)["material"] = "gold"; }, "parameters[9].material", "unknown material \"gold\""},
    {"zero axis", [](json& j) { param(j, kTranslate)["axis"] = {0, 0, 0}; }, "parameters[0].axis", "zero axis"},
    {"zero rotation axis", [](json& j) { param(j, kRotate)["axis"] = {0, 0, 0}; }, "parameters[1].axis", "zero axis"},
    {"zero light axis", [](json& j) { param(j, kLight)["axis"] = {0, 0, 0}; }, "parameters[6].axis", "zero axis"},
    {"missing axis", [](json& j) { param(j, kTranslate).erase("axis"); }, "parameters[0].axis", "missing required field"},
    {"short axis", [](json& j) { param(j, kTranslate)["axis"] = {1, 0}; }, "parameters[0].axis", "wrong length"},
    {"zero direction", [](json& j) { param(j, kDisplace)["direction"] = {0, 0, 0}; }, "parameters[3].direction", "zero direction"},
    {"vertex out of range", [](json& j) { param(j, kDisplace)["vertices"] = {4, 9}; }, "parameters[3].vertices[1]", "out of range (shape \"ground\" has 9 vertices)"},
    {"negative vertex", [](json& j) { param(j, kDisplace)["vertices"] = {-1}; }, "parameters[3].vertices[0]", "out of range"},
    {"vertex twice", [](json& j) { param(j, kDisplace)["vertices"] = {4, 1, 4}; }, "parameters[3].vertices[2]", "given twice"},
    {"no vertices", [](json& j) { param(j, kDisplace)["vertices"] = json::array(); }, "parameters[3].vertices", "empty vertex list"},
    {"vertices word", [](json& j) { param(j, kDisplace)["vertices"] = "some"; }, "parameters[3].vertices", "unknown value"},
    {"heights of a sphere", [](json& j) { param(j, kHeights)["shape"] = "ball"; }, "parameters[5].shape", "not a heightfield"},
    {"heights of nothing", [](json& j) { param(j, kHeights)["shape"] = "hill"; }, "parameters[5].shape", "unknown shape"},
    {"bad prefix", [](json& j) { param(j, kHeights)["name_prefix"] = "h "; }, "parameters[5].name_prefix", "invalid name prefix"},
    // Parameters whose derivative would be identically zero.
    {"albedo of an unused material", [](json& j) { param(j, kAlbedo)["material"] = "unused"; }, "parameters[9].material", "used by no shape"},
    {"albedo of a dielectric", [](json& j) { param(j, kAlbedo)["material"] = "glass"; }, "parameters[9].material", "no albedo"},
    {"roughness of a diffuse material", [](json& j) { param(j, kRoughness)["material"] = "m"; }, "parameters[10].material", "no roughness"},
    {"ior of a conductor", [](json& j) { param(j, kIor)["material"] = "metal"; }, "parameters[12].material", "not a dielectric"},
    {"emission of a dark shape", [](json& j) { param(j, kEmission)["shape"] = "ball"; }, "parameters[7].shape", "does not emit"},
    {"intensity of a dark light", [](json& j) { j["lights"][0]["intensity"] = 0; }, "parameters[8].light", "dark"},
    {"centre of a steady gate", [](json& j) { j["gate"] = {{"type", "steady"}}; }, "parameters[13].type", "steady"},
};

class ParameterErrorCase : public testing::TestWithParam<BadCase> {};

TEST_P(ParameterErrorCase, NamesFileFieldAndProblem) {
  json scene = baseScene();
  GetParam().edit(scene);
  const std::string message = errorOf([&] { parse(scene); });
  ASSERT_FALSE(message.empty()) << "accepted: " << scene["parameters"].dump();
  EXPECT_NE(message.find(std::string(kFile) + ": "), std::string::npos) << message;
  EXPECT_NE(message.find(std::string(GetParam().field) + ": "), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().keyword), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Table, ParameterErrorCase, testing::ValuesIn(kCases), test::tableCaseName<BadCase>);

TEST(Parameters, IndicesInTheErrorTableAreRight) {
  const json j = baseScene();
  EXPECT_EQ(j["parameters"][kTranslate]["type"], "translate");
  EXPECT_EQ(j["parameters"][kRotate]["type"], "rotate");
  EXPECT_EQ(j["parameters"][kDisplace]["type"], "displace");
  EXPECT_EQ(j["parameters"][kHeights]["type"], "heightfield_heights");
  EXPECT_EQ(j["parameters"][kLight]["type"], "light_position");
  EXPECT_EQ(j["parameters"][kEmission]["type"], "emission");
  EXPECT_EQ(j["parameters"][kIntensity]["type"], "intensity");
  EXPECT_EQ(j["parameters"][kAlbedo]["type"], "albedo");
  EXPECT_EQ(j["parameters"][kRoughness]["type"], "roughness");
  EXPECT_EQ(j["parameters"][kIor]["type"], "ior");
  EXPECT_EQ(j["parameters"][kGate]["type"], "gate_center");
}

TEST(Parameters, HeightPrefixDefaultsToTheShapeName) {
  json file = baseScene();
  param(file, kHeights).erase("name_prefix");
  const Scene scene = parse(file);
  EXPECT_EQ(selectParameters(scene, "ground_h*").size(), 9u);
}

// Programmatic scenes get the same checks when they are used.
TEST(Parameters, ProblemsOfHandBuiltParameters) {
  Scene scene = parse(baseScene());
  Parameter p;
  p.name = "slide";
  p.kind = ParameterKind::Translate;
  p.target = "ball";
  p.axis = glm::vec3(2, 0, 0);
  EXPECT_NE(parameterProblem(scene, p).find("unit vector"), std::string::npos);
  p.axis = glm::vec3(1, 0, 0);
  EXPECT_EQ(parameterProblem(scene, p), "");
  p.name = "bad name";
  EXPECT_NE(parameterProblem(scene, p).find("invalid parameter name"), std::string::npos);
  p.name = "slide";
  p.kind = ParameterKind::Displace;
  p.vertices = {1000};
  EXPECT_NE(parameterProblem(scene, p).find("out of range"), std::string::npos);
  p.vertices = {};
  EXPECT_NE(parameterProblem(scene, p).find("no vertices"), std::string::npos);
  p.kind = ParameterKind::Intensity;
  EXPECT_NE(parameterProblem(scene, p).find("unknown light \"ball\""), std::string::npos);
  p.vertices = {1000};
  p.kind = ParameterKind::Displace;
  scene.parameters.push_back(p);
  const std::string message = errorOf([&] { perturbScene(scene, "slide", 0.1); });
  EXPECT_NE(message.find("slide: vertex index 1000 out of range"), std::string::npos) << message;
}

// Every example scene's parameters bind and perturb; the occluder scene moves its occluder.
TEST(Parameters, ExampleScenesDeclareUsableParameters) {
  size_t withParameters = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene scene = loadScene(entry.path());
    if (scene.parameters.empty()) continue;
    ++withParameters;
    const std::vector<std::string> all = selectParameters(scene, "*");
    EXPECT_EQ(all.size(), scene.parameters.size());
    EXPECT_EQ(bindParameters(scene, all).size(), all.size());
    for (const std::string& name : all) {
      EXPECT_NO_THROW(perturbScene(scene, name, 1e-3)) << name;
      EXPECT_NO_THROW(perturbScene(scene, name, -1e-3)) << name;
    }
  }
  EXPECT_GE(withParameters, 4u);

  const Scene occluder = loadScene(kScenes / "occluder_shadow.json");
  const ParameterBinding slide = bindParameters(occluder, {"occluder_x"})[0];
  EXPECT_EQ(slide.kind, ParameterKind::Translate);
  EXPECT_EQ(occluder.shapes[slide.target].name, "occluder");
  EXPECT_EQ(occluder.shapes[slide.target].emission, 0.0f);

  const Scene stack = loadScene(kScenes / "transient_stack.json");
  EXPECT_EQ(selectParameters(stack, "terrain_h*").size(), 16u);
}

}  // namespace
}  // namespace vktg
