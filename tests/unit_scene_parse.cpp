// Valid JSON scenes: the example scenes, defaults, every field's effect, the default scene.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "scene/primitives.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(VKTG_SOURCE_DIR) / "scenes";
const fs::path kData = VKTG_TEST_DATA;

Scene parse(const std::string& text) { return parseSceneJson(text, "test.json", kData); }

// A valid scene with one emissive square; tests splice their fields in.
std::string minimalScene(const std::string& extra = "", const std::string& shapes =
                             R"([{"type": "rectangle", "emission": 1}])") {
  return R"({"version": 1, "camera": {"type": "perspective", "position": [0, 0, 3], "look_at": [0, 0, 0]},
             "shapes": )" + shapes + (extra.empty() ? "" : ", " + extra) + "}";
}

glm::vec3 normalOf(const Shape& s, size_t i) {
  const glm::uvec3 t = s.triangles[i];
  return glm::normalize(glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]));
}

glm::vec3 centroid(const Shape& s) {
  glm::vec3 sum(0);
  for (const glm::vec3& p : s.positions) sum += p;
  return sum / float(s.positions.size());
}

const Shape& shapeNamed(const Scene& scene, const std::string& name) {
  for (const Shape& s : scene.shapes)
    if (s.name == name) return s;
  throw std::runtime_error("no shape " + name);
}

TEST(SceneParse, EveryExampleSceneLoads) {
  size_t count = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene scene = loadScene(entry.path());
    EXPECT_EQ(scene.source, entry.path());
    EXPECT_TRUE(scene.hasEmitters());
    EXPECT_GT(scene.triangleCount(), 0u);
    for (const Shape& s : scene.shapes) EXPECT_LT(s.material, scene.materials.size());
    ++count;
  }
  EXPECT_GE(count, 4u);
}

// The complete example in docs/scene-format.md must stay valid; its mesh file is stood in for
// by the test model.
TEST(SceneParse, DocumentationExampleParses) {
  std::ifstream in(fs::path(VKTG_SOURCE_DIR) / "docs" / "scene-format.md");
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const size_t begin = text.find("```json\n");
  ASSERT_NE(begin, std::string::npos);
  const size_t end = text.find("```", begin + 8);
  const std::string example = text.substr(begin + 8, end - begin - 8);
  const fs::path dir = fs::temp_directory_path() / ("vktg_doc_example_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(kData / "tiny.glb", dir / "bunny.glb", fs::copy_options::overwrite_existing);
  Scene scene;
  EXPECT_NO_THROW(scene = parseSceneJson(example, "scene-format.md", dir));
  fs::remove_all(dir);
  EXPECT_EQ(scene.shapes.size(), 6u);
  EXPECT_EQ(scene.gate.type, GateType::Gaussian);
  EXPECT_DOUBLE_EQ(scene.gate.mu, 16 * kSpeedOfLight);
}

TEST(SceneParse, ExampleScenesHaveTheirDocumentedFeatures) {
  const Scene confocal = loadScene(kScenes / "confocal_plane.json");
  EXPECT_EQ(confocal.camera.type, CameraType::PointSensor);
  ASSERT_EQ(confocal.pointLights.size(), 1u);
  EXPECT_EQ(confocal.pointLights[0].position, confocal.camera.position);  // co-located
  EXPECT_EQ(confocal.gate.type, GateType::Gaussian);
  // The sensor is h = 1 above the plane and the gate is centred at 2h.
  const float h = confocal.camera.position.y - confocal.shapes[0].positions[0].y;
  EXPECT_NEAR(h, 1.0f, 1e-6f);
  EXPECT_NEAR(confocal.gate.mu, 2.0 * h, 1e-5);

  const Scene glossy = loadScene(kScenes / "glossy_glass.json");
  bool conductor = false, dielectric = false;
  for (const Material& m : glossy.materials) {
    conductor = conductor || m.type == MaterialType::Conductor;
    dielectric = dielectric || m.type == MaterialType::Dielectric;
  }
  EXPECT_TRUE(conductor && dielectric);

  const Scene stack = loadScene(kScenes / "transient_stack.json");
  EXPECT_EQ(stack.gate.type, GateType::Bins);
  EXPECT_GT(stack.gate.layers(), 1u);
}

void expectSameScene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    EXPECT_EQ(a.materials[i].name, b.materials[i].name);
    EXPECT_EQ(a.materials[i].type, b.materials[i].type);
    EXPECT_EQ(a.materials[i].albedo, b.materials[i].albedo);
  }
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (size_t i = 0; i < a.shapes.size(); ++i) {
    const Shape &sa = a.shapes[i], &sb = b.shapes[i];
    SCOPED_TRACE(sa.name);
    EXPECT_EQ(sa.name, sb.name);
    EXPECT_EQ(sa.material, sb.material);
    EXPECT_EQ(sa.emission, sb.emission);
    EXPECT_EQ(sa.triangles, sb.triangles);
    ASSERT_EQ(sa.positions.size(), sb.positions.size());
    for (size_t k = 0; k < sa.positions.size(); ++k) EXPECT_LT(glm::distance(sa.positions[k], sb.positions[k]), 1e-5f);
  }
  EXPECT_EQ(a.pointLights.size(), b.pointLights.size());
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (size_t i = 0; i < a.parameters.size(); ++i) {
    const Parameter &pa = a.parameters[i], &pb = b.parameters[i];
    SCOPED_TRACE(pa.name);
    EXPECT_EQ(pa.name, pb.name);
    EXPECT_EQ(pa.kind, pb.kind);
    EXPECT_EQ(pa.target, pb.target);
    EXPECT_EQ(pa.axis, pb.axis);
    EXPECT_LT(glm::distance(pa.center, pb.center), 1e-5f);
  }
  EXPECT_EQ(a.camera.type, b.camera.type);
  EXPECT_EQ(a.camera.position, b.camera.position);
  EXPECT_EQ(a.camera.lookAt, b.camera.lookAt);
  EXPECT_EQ(a.camera.up, b.camera.up);
  EXPECT_EQ(a.camera.fovY, b.camera.fovY);
  EXPECT_EQ(a.camera.width, b.camera.width);
  EXPECT_EQ(a.camera.height, b.camera.height);
  EXPECT_EQ(a.gate.type, b.gate.type);
  EXPECT_EQ(a.gate.a, b.gate.a);
  EXPECT_EQ(a.gate.b, b.gate.b);
  EXPECT_EQ(a.render.spp, b.render.spp);
  EXPECT_EQ(a.render.maxDepth, b.render.maxDepth);
  EXPECT_EQ(a.render.rouletteDepth, b.render.rouletteDepth);
  EXPECT_EQ(a.render.seed, b.render.seed);
  EXPECT_EQ(a.render.nee, b.render.nee);
}

TEST(SceneParse, CornellBoxFileIsTheDefaultScene) {
  expectSameScene(loadScene(kScenes / "cornell_box.json"), defaultScene());
}

TEST(SceneParse, DefaultSceneGeometryFacesIntoTheRoom) {
  const Scene scene = defaultScene();
  EXPECT_TRUE(scene.source.empty());
  EXPECT_TRUE(scene.hasEmitters());
  EXPECT_EQ(scene.triangleCount(), 5u * 2u + 2u + 2u * 12u);
  const glm::vec3 roomCentre(0, 1, 0);
  for (const char* wall : {"floor", "ceiling", "back", "left", "right"}) {
    const Shape& s = shapeNamed(scene, wall);
    EXPECT_NEAR(meshArea(s.positions, s.triangles), 4.0, 1e-5) << wall;
    for (size_t i = 0; i < s.triangles.size(); ++i)
      EXPECT_NEAR(glm::dot(normalOf(s, i), glm::normalize(roomCentre - centroid(s))), 1.0f, 1e-5f) << wall;
  }
  const Shape& light = shapeNamed(scene, "light");
  EXPECT_GT(light.emission, 0.0f);
  for (size_t i = 0; i < light.triangles.size(); ++i) EXPECT_NEAR(normalOf(light, i).y, -1.0f, 1e-6f);
  for (const glm::vec3& p : light.positions) EXPECT_LT(p.y, 2.0f);  // below the ceiling, not in it
  EXPECT_EQ(scene.materials[shapeNamed(scene, "left").material].albedo, 0.6f);
  EXPECT_EQ(scene.materials[shapeNamed(scene, "right").material].albedo, 0.4f);
  EXPECT_EQ(scene.materials[shapeNamed(scene, "floor").material].albedo, 0.8f);
  // Both boxes stand on the floor inside the room.
  for (const char* box : {"short_box", "tall_box"}) {
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& p : shapeNamed(scene, box).positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    EXPECT_NEAR(lo.y, 0.0f, 1e-6f) << box;
    EXPECT_GT(lo.x, -1.0f);
    EXPECT_LT(hi.x, 1.0f);
    EXPECT_GT(lo.z, -1.0f);
    EXPECT_LT(hi.z, 1.0f);
  }
  EXPECT_EQ(scene.camera.position, glm::vec3(0, 1, 3.8f));
  EXPECT_EQ(scene.camera.width, 128u);
  EXPECT_EQ(scene.render.spp, 64u);
  // The gate must let the directly seen light through: camera to light centre.
  const double toLight = glm::distance(scene.camera.position, centroid(light));
  EXPECT_GT(scene.gate.weight(toLight), 0.0);
}

TEST(SceneParse, DefaultsApplyWhenFieldsAreOmitted) {
  const Scene scene = parse(minimalScene());
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "default");
  EXPECT_EQ(scene.materials[0].type, MaterialType::Diffuse);
  EXPECT_FLOAT_EQ(scene.materials[0].albedo, 0.8f);
  EXPECT_EQ(scene.shapes[0].material, 0u);
  EXPECT_EQ(scene.shapes[0].name, "rectangle_0");
  EXPECT_EQ(scene.gate.type, GateType::Steady);
  EXPECT_EQ(scene.camera.up, glm::vec3(0, 1, 0));
  EXPECT_EQ(scene.camera.fovY, 40.0f);
  EXPECT_EQ(scene.camera.width, 64u);
  EXPECT_EQ(scene.camera.height, 64u);
  const RenderSettings defaults;
  EXPECT_EQ(scene.render.spp, defaults.spp);
  EXPECT_EQ(scene.render.maxDepth, defaults.maxDepth);
  EXPECT_EQ(scene.render.rouletteDepth, defaults.rouletteDepth);
  EXPECT_EQ(scene.render.nee, NeeMode::Auto);
  EXPECT_EQ(scene.source, fs::path("test.json"));
}

TEST(SceneParse, MaterialsAndRenderSettings) {
  const Scene scene = parse(minimalScene(
      R"("materials": {"m": {"type": "conductor", "albedo": 0.3, "roughness": 0.05},
                       "g": {"type": "dielectric", "ior": 1.33, "roughness": 0.5},
                       "default": {"type": "diffuse", "albedo": 0.1}},
         "render": {"spp": 7, "max_depth": 5, "roulette_depth": 2, "seed": 42, "nee": "ellipsoidal"})",
      R"([{"type": "rectangle", "emission": 2, "material": "m"}, {"type": "cube", "material": "g"},
          {"type": "cube"}])"));
  ASSERT_EQ(scene.materials.size(), 3u);  // a user-defined "default" replaces the built-in one
  const Material& m = scene.materials[scene.shapes[0].material];
  EXPECT_EQ(m.type, MaterialType::Conductor);
  EXPECT_FLOAT_EQ(m.albedo, 0.3f);
  EXPECT_FLOAT_EQ(m.roughness, 0.05f);
  const Material& g = scene.materials[scene.shapes[1].material];
  EXPECT_EQ(g.type, MaterialType::Dielectric);
  EXPECT_FLOAT_EQ(g.ior, 1.33f);
  EXPECT_FLOAT_EQ(g.roughness, 0.5f);
  EXPECT_FLOAT_EQ(scene.materials[scene.shapes[2].material].albedo, 0.1f);
  EXPECT_EQ(scene.shapes[0].emission, 2.0f);
  EXPECT_EQ(scene.render.spp, 7u);
  EXPECT_EQ(scene.render.maxDepth, 5u);
  EXPECT_EQ(scene.render.rouletteDepth, 2u);
  EXPECT_EQ(scene.render.seed, 42u);
  EXPECT_EQ(scene.render.nee, NeeMode::Ellipsoidal);
}

TEST(SceneParse, GateForms) {
  const double c = kSpeedOfLight;
  Gate g = parse(minimalScene(R"("gate": {"type": "box", "a": "10ns", "b": "4.5m"})")).gate;
  EXPECT_EQ(g.type, GateType::Box);
  EXPECT_DOUBLE_EQ(g.a, 10 * c);
  EXPECT_DOUBLE_EQ(g.b, 4.5);
  g = parse(minimalScene(R"("gate": {"type": "gaussian", "mu": 2.5, "sigma": "0.1ns", "normalize": true})")).gate;
  EXPECT_EQ(g.type, GateType::Gaussian);
  EXPECT_DOUBLE_EQ(g.mu, 2.5);
  EXPECT_DOUBLE_EQ(g.sigma, 0.1 * c);
  EXPECT_TRUE(g.normalize);
  g = parse(minimalScene(R"("gate": {"type": "truncated_gaussian", "mu": 3, "sigma": 0.5, "a": 2, "b": 4})")).gate;
  EXPECT_EQ(g.type, GateType::TruncatedGaussian);
  EXPECT_DOUBLE_EQ(g.a, 2.0);
  EXPECT_DOUBLE_EQ(g.b, 4.0);
  g = parse(minimalScene(R"("gate": {"type": "bins", "start": 1, "width": 0.25, "count": 12})")).gate;
  EXPECT_EQ(g.type, GateType::Bins);
  EXPECT_DOUBLE_EQ(g.binStart, 1.0);
  EXPECT_DOUBLE_EQ(g.binWidth, 0.25);
  EXPECT_EQ(g.binCount, 12u);
  g = parse(minimalScene(R"("gate": {"spec": "box:3,5"})")).gate;
  EXPECT_EQ(g.type, GateType::Box);
  EXPECT_DOUBLE_EQ(g.a, 3.0);
  EXPECT_DOUBLE_EQ(g.b, 5.0);
  EXPECT_EQ(parse(minimalScene(R"("gate": {"type": "steady"})")).gate.type, GateType::Steady);
}

TEST(SceneParse, PointSensorCamera) {
  const Scene scene = parse(R"({"version": 1, "camera": {"type": "point_sensor", "position": [0, 2, 0], "normal": [0, -3, 0]},
                                "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 2.5}]})");
  EXPECT_EQ(scene.camera.type, CameraType::PointSensor);
  EXPECT_EQ(scene.camera.normal, glm::vec3(0, -1, 0));
  EXPECT_EQ(scene.camera.width, 1u);
  EXPECT_EQ(scene.camera.height, 1u);
  ASSERT_EQ(scene.pointLights.size(), 1u);
  EXPECT_EQ(scene.pointLights[0].name, "light_0");
  EXPECT_EQ(scene.pointLights[0].intensity, 2.5f);
  EXPECT_TRUE(scene.hasEmitters());
  EXPECT_EQ(scene.triangleCount(), 0u);
}

TEST(SceneParse, PerspectiveCameraFields) {
  const Scene scene = parse(R"({"version": 1, "camera": {"type": "perspective", "position": [1, 2, 3], "look_at": [0, 0, 0],
                                "up": [0, 0, 2], "fov_y": 25.5, "resolution": [320, 200]},
                                "shapes": [{"type": "cube", "emission": 1}]})");
  EXPECT_EQ(scene.camera.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(scene.camera.up, glm::vec3(0, 0, 1));  // normalised
  EXPECT_EQ(scene.camera.fovY, 25.5f);
  EXPECT_EQ(scene.camera.width, 320u);
  EXPECT_EQ(scene.camera.height, 200u);
}

TEST(SceneParse, ShapeTransformsAndTypes) {
  const Scene scene = parse(minimalScene("", R"([
      {"name": "ball", "type": "sphere", "subdivisions": 2, "emission": 1,
       "transform": {"translate": [1, 2, 3], "scale": 0.5}},
      {"name": "box", "type": "cube", "transform": {"rotate": [0, 45, 0], "scale": [1, 2, 3]}},
      {"name": "ground", "type": "heightfield", "resolution": [3, 2], "size": [4, 1], "heights": [0, 1, 0, 0, 1, 0],
       "transform": {"translate": [0, -1, 0]}}])"));
  const Shape& ball = shapeNamed(scene, "ball");
  EXPECT_EQ(ball.triangles.size(), 20u * 16u);
  for (const glm::vec3& p : ball.positions) EXPECT_NEAR(glm::distance(p, glm::vec3(1, 2, 3)), 0.5f, 1e-6f);
  for (size_t i = 0; i < ball.triangles.size(); ++i)
    EXPECT_GT(glm::dot(normalOf(ball, i), ball.positions[ball.triangles[i].x] - glm::vec3(1, 2, 3)), 0.0f);
  const Shape& box = shapeNamed(scene, "box");
  EXPECT_NEAR(meshArea(box.positions, box.triangles), 8.0 * (1 * 2 + 2 * 3 + 1 * 3), 1e-4);
  const Shape& ground = shapeNamed(scene, "ground");
  EXPECT_EQ(ground.triangles.size(), 4u);
  EXPECT_EQ(ground.positions[1], glm::vec3(0, 0, -0.5f));  // (i=1, j=0): height 1, moved down by 1
  EXPECT_EQ(ground.positions[0], glm::vec3(-2, -1, -0.5f));
  EXPECT_EQ(ground.grid, glm::uvec2(3, 2));
  EXPECT_EQ(box.grid, glm::uvec2(0, 0));
}

TEST(SceneParse, MeshShapeFromGltf) {
  const Scene scene = parse(minimalScene(R"("materials": {"m": {"type": "diffuse", "albedo": 0.25}})",
                                         R"([{"name": "model", "type": "mesh", "file": "tiny.gltf", "material": "m",
                                              "emission": 3, "transform": {"translate": [10, 0, 0]}}])"));
  ASSERT_EQ(scene.shapes.size(), 1u);  // the file's primitives merge into the one named shape
  const Shape& s = scene.shapes[0];
  EXPECT_EQ(s.name, "model");
  EXPECT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.emission, 3.0f);
  EXPECT_FLOAT_EQ(scene.materials[s.material].albedo, 0.25f);
  // The quad node sits at z = -1 in the file; the JSON transform moves it by +10 in x.
  EXPECT_NEAR(s.positions[0].x, 9.0f, 1e-6f);
  EXPECT_NEAR(s.positions[0].z, -1.0f, 1e-6f);
}

TEST(SceneParse, SceneBoundsCoverShapesLightsAndCamera) {
  Scene scene = parse(minimalScene(R"("lights": [{"type": "point", "position": [0, 5, 0]}])"));
  glm::vec3 lo, hi;
  sceneBounds(scene, lo, hi);
  EXPECT_EQ(lo, glm::vec3(-1, -1, 0));
  EXPECT_EQ(hi, glm::vec3(1, 5, 3));  // the light's y and the camera's z
  EXPECT_EQ(scene.triangleCount(), 2u);
}

TEST(SceneParse, HasEmittersNeedsPositiveEmissionOrIntensity) {
  Scene scene;
  EXPECT_FALSE(scene.hasEmitters());
  Shape dark;
  dark.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  dark.triangles = {{0, 1, 2}};
  scene.shapes.push_back(dark);
  EXPECT_FALSE(scene.hasEmitters());
  scene.pointLights.push_back(PointLight{"off", {}, 0.0f});
  EXPECT_FALSE(scene.hasEmitters());
  scene.pointLights[0].intensity = 1.0f;
  EXPECT_TRUE(scene.hasEmitters());
  scene.pointLights.clear();
  scene.shapes[0].emission = 0.5f;
  EXPECT_TRUE(scene.hasEmitters());
}


// "value" and "values" load the scene with its parameters already applied (the form in which
// `vktg optimize` writes its result): the same scene as applying them by hand.
TEST(SceneParse, ParameterValuesAreAppliedAtLoad) {
  const std::string shapes = R"(
    "camera": {"type": "perspective", "position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]},
    "gate": {"type": "box", "a": 1, "b": 5},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"name": "lamp", "type": "rectangle", "material": "m", "emission": 1},
               {"name": "ground", "type": "heightfield", "material": "m", "resolution": [2, 2], "size": [1, 1],
                "heights": [0, 0, 0, 0]}],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 0], "intensity": 1}],)";
  const Scene plain = parse(R"({"version": 1,)" + shapes + R"(
    "parameters": [{"name": "lift", "type": "translate", "shape": "lamp", "axis": [0, 1, 0]},
                   {"name": "grey", "type": "albedo", "material": "m"},
                   {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"}]})");
  const Scene valued = parse(R"({"version": 1,)" + shapes + R"(
    "parameters": [{"name": "lift", "type": "translate", "shape": "lamp", "axis": [0, 1, 0], "value": 0.25},
                   {"name": "grey", "type": "albedo", "material": "m", "value": -0.125},
                   {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h", "values": [0, 0.5, 0, -0.5]}]})");
  EXPECT_FLOAT_EQ(valued.materials[0].albedo, 0.375f);
  const Shape& lamp = shapeNamed(valued, "lamp");
  for (size_t i = 0; i < lamp.positions.size(); ++i)
    EXPECT_NEAR(lamp.positions[i].y, shapeNamed(plain, "lamp").positions[i].y + 0.25f, 1e-6f);
  const Shape& ground = shapeNamed(valued, "ground");
  EXPECT_NEAR(ground.positions[1].y, 0.5f, 1e-6f);
  EXPECT_NEAR(ground.positions[3].y, -0.5f, 1e-6f);
  EXPECT_NEAR(ground.positions[0].y, 0.0f, 1e-6f);
  // The parameters stay declared (θ = 0 now means "at these values").
  EXPECT_EQ(valued.parameters.size(), plain.parameters.size());
  try {
    parse(R"({"version": 1,)" + shapes + R"(
      "parameters": [{"type": "heightfield_heights", "shape": "ground", "values": [0, 1]}]})");
    FAIL() << "values of the wrong length were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("parameters[0].values"), std::string::npos) << e.what();
  }
}

// "vertex_positions": three displacements per vertex along the world axes, named <prefix><k>_x, _y,
// _z in vertex order, for any shape; its "values" move the vertices at load like any value.
TEST(SceneParse, VertexPositionsExpandToThreeAxesPerVertex) {
  const std::string shapes = R"(
    "camera": {"type": "perspective", "position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"name": "lamp", "type": "rectangle", "material": "m", "emission": 1},
               {"name": "panel", "type": "rectangle", "material": "m", "transform": {"translate": [0, 0, -1]}}],)";
  const Scene plain = parse(R"({"version": 1,)" + shapes + R"(
    "parameters": [{"type": "vertex_positions", "shape": "panel"}]})");
  const Shape& panel = shapeNamed(plain, "panel");
  ASSERT_EQ(plain.parameters.size(), 3 * panel.positions.size());
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const char* suffixes[3] = {"_x", "_y", "_z"};
  for (size_t i = 0; i < plain.parameters.size(); ++i) {
    const Parameter& p = plain.parameters[i];
    EXPECT_EQ(p.name, "panel_v" + std::to_string(i / 3) + suffixes[i % 3]);
    EXPECT_EQ(p.kind, ParameterKind::Displace);
    EXPECT_EQ(p.target, "panel");
    EXPECT_EQ(p.axis, axes[i % 3]);
    EXPECT_EQ(p.vertices, std::vector<uint32_t>{uint32_t(i / 3)});
  }
  const Scene valued = parse(R"({"version": 1,)" + shapes + R"(
    "parameters": [{"type": "vertex_positions", "shape": "panel", "name_prefix": "p",
                    "values": [0, 0, 0, 0.25, -0.5, 0.125, 0, 0, 0, 0, 0, 0]}]})");
  EXPECT_EQ(valued.parameters[4].name, "p1_y");
  const Shape& moved = shapeNamed(valued, "panel");
  EXPECT_NEAR(moved.positions[1].x, panel.positions[1].x + 0.25f, 1e-6f);
  EXPECT_NEAR(moved.positions[1].y, panel.positions[1].y - 0.5f, 1e-6f);
  EXPECT_NEAR(moved.positions[1].z, panel.positions[1].z + 0.125f, 1e-6f);
  EXPECT_EQ(moved.positions[0], panel.positions[0]);
  EXPECT_EQ(moved.positions[2], panel.positions[2]);
  const auto errorOf = [&](const std::string& parameters) {
    try {
      parse(R"({"version": 1,)" + shapes + R"("parameters": )" + parameters + "}");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(errorOf(R"([{"type": "vertex_positions", "shape": "panel", "values": [0, 1, 2, 3]}])")
                .find("parameters[0].values"), std::string::npos);
  EXPECT_NE(errorOf(R"([{"type": "vertex_positions", "shape": "wall"}])").find("unknown shape \"wall\""), std::string::npos);
  EXPECT_NE(errorOf(R"([{"type": "vertex_positions", "shape": "panel", "name_prefix": "a b"}])").find("invalid name prefix"),
            std::string::npos);
  EXPECT_NE(errorOf(R"([{"name": "panel_v2_z", "type": "translate", "shape": "lamp", "axis": [0, 1, 0]},
                        {"type": "vertex_positions", "shape": "panel"}])")
                .find("duplicate parameter name \"panel_v2_z\""), std::string::npos);
}

}  // namespace
}  // namespace vktg
