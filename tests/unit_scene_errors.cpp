// Bad scene input: every class of mistake gives one vktg::Error naming the file, the JSON path of
// the field and the problem. Each case edits a valid base scene in one place, so a case can only
// pass if that one edit is what the parser rejects.
#include <filesystem>
#include <fstream>
#include <functional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/table_case_name.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kData = VKTG_TEST_DATA;
const char* kFile = "bad_scene.json";

json baseScene() {
  return json::parse(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]},
    "gate": {"type": "box", "a": 1, "b": 5},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5},
                  "metal": {"type": "conductor", "albedo": 0.5, "roughness": 0.3},
                  "glass": {"type": "dielectric", "roughness": 0.3, "ior": 1.5}},
    "shapes": [{"name": "lamp", "type": "rectangle", "material": "m", "emission": 1,
                "transform": {"translate": [0, 0, 0], "rotate": [0, 0, 0], "scale": 1}},
               {"name": "ground", "type": "heightfield", "resolution": [2, 2], "size": [1, 1], "heights": [0, 0, 0, 0]}],
    "lights": [{"type": "point", "name": "laser", "position": [0, 1, 0], "intensity": 1}],
    "render": {"spp": 4, "nee": "auto"}
  })");
}

struct BadCase {
  const char* name;
  std::function<void(json&)> edit;
  const char* field;    // JSON path the message must name
  const char* keyword;  // the problem the message must name
};

std::string errorFor(const std::string& text, const fs::path& baseDir = kData) {
  try {
    parseSceneJson(text, kFile, baseDir);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SceneErrors, BaseSceneIsValid) { EXPECT_EQ(errorFor(baseScene().dump()), ""); }

const BadCase kCases[] = {
    // Unknown fields, at every level.
    {"unknown top-level field", [](json& j) { j["colour"] = 1; }, "colour", "unknown field"},
    {"unknown camera field", [](json& j) { j["camera"]["fov"] = 40; }, "camera.fov", "unknown field"},
    {"unknown shape field", [](json& j) { j["shapes"][0]["emision"] = 1; }, "shapes[0].emision", "unknown field"},
    {"unknown material field", [](json& j) { j["materials"]["m"]["albdo"] = 1; }, "materials.m.albdo", "unknown field"},
    {"field of another material type", [](json& j) { j["materials"]["m"]["roughness"] = 0.5; }, "materials.m.roughness", "unknown field"},
    {"unknown transform field", [](json& j) { j["shapes"][0]["transform"]["rotation"] = {0, 0, 0}; }, "shapes[0].transform.rotation", "unknown field"},
    {"unknown gate field", [](json& j) { j["gate"]["c"] = 1; }, "gate.c", "unknown field"},
    {"unknown light field", [](json& j) { j["lights"][0]["color"] = 1; }, "lights[0].color", "unknown field"},
    {"unknown render field", [](json& j) { j["render"]["samples"] = 4; }, "render.samples", "unknown field"},
    {"unknown shape type", [](json& j) { j["shapes"][0]["type"] = "disk"; }, "shapes[0].type", "unknown type"},
    {"unknown material type", [](json& j) { j["materials"]["m"]["type"] = "plastic"; }, "materials.m.type", "unknown type"},
    {"unknown gate type", [](json& j) { j["gate"]["type"] = "boxcar"; }, "gate.type", "unknown type"},
    {"unknown camera type", [](json& j) { j["camera"]["type"] = "orthographic"; }, "camera.type", "unknown type"},
    {"unknown nee mode", [](json& j) { j["render"]["nee"] = "fast"; }, "render.nee", "unknown value"},
    // Wrong types.
    {"number as string", [](json& j) { j["camera"]["fov_y"] = "40"; }, "camera.fov_y", "wrong type"},
    {"albedo as string", [](json& j) { j["materials"]["m"]["albedo"] = "0.5"; }, "materials.m.albedo", "wrong type"},
    {"shapes not an array", [](json& j) { j["shapes"] = json::object(); }, "shapes", "wrong type"},
    {"materials not an object", [](json& j) { j["materials"] = json::array(); }, "materials", "wrong type"},
    {"vector too short", [](json& j) { j["camera"]["position"] = {0, 0}; }, "camera.position", "wrong length"},
    {"vector element not a number", [](json& j) { j["lights"][0]["position"][1] = true; }, "lights[0].position[1]", "wrong type"},
    {"boolean expected", [](json& j) { j["gate"] = {{"type", "gaussian"}, {"mu", 1}, {"sigma", 0.1}, {"normalize", 1}}; }, "gate.normalize", "wrong type"},
    {"fractional integer", [](json& j) { j["render"]["spp"] = 2.5; }, "render.spp", "integer"},
    {"name not a string", [](json& j) { j["shapes"][0]["name"] = 3; }, "shapes[0].name", "wrong type"},
    // Missing required fields.
    {"missing version", [](json& j) { j.erase("version"); }, "version", "missing required field"},
    {"missing camera", [](json& j) { j.erase("camera"); }, "camera", "missing required field"},
    {"missing camera position", [](json& j) { j["camera"].erase("position"); }, "camera.position", "missing required field"},
    {"missing shape type", [](json& j) { j["shapes"][0].erase("type"); }, "shapes[0].type", "missing required field"},
    {"missing gate bound", [](json& j) { j["gate"].erase("b"); }, "gate.b", "missing required field"},
    {"missing light position", [](json& j) { j["lights"][0].erase("position"); }, "lights[0].position", "missing required field"},
    {"missing heights", [](json& j) { j["shapes"][1].erase("heights"); }, "shapes[1].heights", "missing required field"},
    // Versions.
    {"future version", [](json& j) { j["version"] = 2; }, "version", "unsupported version"},
    {"version zero", [](json& j) { j["version"] = 0; }, "version", "unsupported version"},
    // Values out of their meaningful range.
    {"albedo above one", [](json& j) { j["materials"]["m"]["albedo"] = 1.5; }, "materials.m.albedo", "out of range"},
    {"negative albedo", [](json& j) { j["materials"]["metal"]["albedo"] = -0.1; }, "materials.metal.albedo", "out of range"},
    {"roughness too small", [](json& j) { j["materials"]["metal"]["roughness"] = 0; }, "materials.metal.roughness", "out of range"},
    {"roughness above one", [](json& j) { j["materials"]["glass"]["roughness"] = 1.5; }, "materials.glass.roughness", "out of range"},
    {"ior of one", [](json& j) { j["materials"]["glass"]["ior"] = 1.0; }, "materials.glass.ior", "out of range"},
    {"negative emission", [](json& j) { j["shapes"][0]["emission"] = -1; }, "shapes[0].emission", "out of range"},
    {"negative intensity", [](json& j) { j["lights"][0]["intensity"] = -2; }, "lights[0].intensity", "out of range"},
    {"zero resolution", [](json& j) { j["camera"]["resolution"] = {0, 8}; }, "camera.resolution[0]", "out of range"},
    {"fov of 180", [](json& j) { j["camera"]["fov_y"] = 180; }, "camera.fov_y", "out of range"},
    {"fov of 0", [](json& j) { j["camera"]["fov_y"] = 0; }, "camera.fov_y", "out of range"},
    {"look_at at position", [](json& j) { j["camera"]["look_at"] = {0, 0, 3}; }, "camera.look_at", "look_at equals position"},
    {"up along view", [](json& j) { j["camera"]["up"] = {0, 0, -1}; }, "camera.up", "parallel"},
    {"zero sensor normal", [](json& j) { j["camera"] = {{"type", "point_sensor"}, {"position", {0, 0, 1}}, {"normal", {0, 0, 0}}}; }, "camera.normal", "must not be zero"},
    {"zero spp", [](json& j) { j["render"]["spp"] = 0; }, "render.spp", "out of range"},
    {"beyond float range", [](json& j) { j["shapes"][0]["transform"]["translate"] = {0, 1e300, 0}; }, "shapes[0].transform.translate[1]", "finite"},
    {"NaN length", [](json& j) { j["gate"]["a"] = "nan"; }, "gate.a", "finite"},
    {"unreadable length", [](json& j) { j["gate"]["a"] = "3 parsecs"; }, "gate.a", "cannot read"},
    {"gate a after b", [](json& j) { j["gate"]["a"] = 6; }, "gate", "a must be < b"},
    {"gate negative sigma", [](json& j) { j["gate"] = {{"type", "gaussian"}, {"mu", 1}, {"sigma", -0.1}}; }, "gate", "sigma must be > 0"},
    {"bad gate spec", [](json& j) { j["gate"] = {{"spec", "box:5"}}; }, "gate.spec", "box"},
    // Geometry.
    {"zero scale", [](json& j) { j["shapes"][0]["transform"]["scale"] = {1, 0, 1}; }, "shapes[0].transform.scale", "zero"},
    {"too many subdivisions", [](json& j) { j["shapes"][0] = {{"type", "sphere"}, {"subdivisions", 9}, {"emission", 1}}; }, "shapes[0].subdivisions", "out of range"},
    {"heights count mismatch", [](json& j) { j["shapes"][1]["heights"] = {0, 0, 0}; }, "shapes[1].heights", "count mismatch"},
    {"heightfield resolution 1", [](json& j) { j["shapes"][1]["resolution"] = {1, 2}; j["shapes"][1]["heights"] = {0, 0}; }, "shapes[1].resolution[0]", "out of range"},
    {"heightfield zero size", [](json& j) { j["shapes"][1]["size"] = {1, 0}; }, "shapes[1].size[1]", "out of range"},
    {"heightfield NaN-like height", [](json& j) { j["shapes"][1]["heights"][2] = nullptr; }, "shapes[1].heights[2]", "wrong type"},
    {"transform past the float range", [](json& j) { j["shapes"][1]["transform"] = {{"scale", 3e38}, {"translate", {3e38, 0, 0}}}; }, "shapes[1]", "past the float range"},
    {"mesh transform past the float range", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "tiny.gltf"}, {"transform", {{"scale", 3e38}, {"rotate", {0, 45, 0}}}}}; }, "shapes[1]", "past the float range"},
    {"area past the float range", [](json& j) { j["shapes"][1]["transform"] = {{"scale", 1e20}}; }, "shapes[1]", "surface area past the float range"},
    {"emitted power past the float range", [](json& j) { j["shapes"][0]["emission"] = 1e38; j["shapes"][0]["transform"]["scale"] = 10; }, "shapes[0].emission", "emitted power"},
    {"zero-area mesh", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "degenerate.gltf"}}; }, "shapes[1]", "zero area"},
    {"empty mesh", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "no_meshes.gltf"}}; }, "shapes[1].file", "empty mesh"},
    {"missing mesh file", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "nowhere.glb"}}; }, "shapes[1].file", "not found"},
    {"malformed mesh file", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "malformed.gltf"}}; }, "shapes[1].file", "malformed glTF"},
    {"unknown mesh file extension", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "tiny.stl"}}; }, "shapes[1].file", "unknown mesh file extension \".stl\""},
    {"missing OBJ mesh file", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "nowhere.obj"}}; }, "shapes[1].file", "not found"},
    {"missing PLY mesh file", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "nowhere.PLY"}}; }, "shapes[1].file", "not found"},
    {"OBJ mesh transform past the float range", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "meshes/prism.obj"}, {"transform", {{"scale", 3e38}, {"rotate", {0, 45, 0}}}}}; }, "shapes[1]", "past the float range"},
    {"PLY mesh area past the float range", [](json& j) { j["shapes"][1] = {{"type", "mesh"}, {"file", "meshes/prism_le.ply"}, {"transform", {{"scale", 1e20}}}}; }, "shapes[1]", "surface area past the float range"},
    // References and names.
    {"unknown material name", [](json& j) { j["shapes"][0]["material"] = "gold"; }, "shapes[0].material", "unknown material"},
    {"duplicate shape name", [](json& j) { j["shapes"][1]["name"] = "lamp"; }, "shapes[1].name", "duplicate name"},
    {"light named like a shape", [](json& j) { j["lights"][0]["name"] = "ground"; }, "lights[0].name", "duplicate name"},
    // Emitters.
    {"summed power past the float range", [](json& j) { j["shapes"][0]["emission"] = 1e38; j["shapes"][0]["transform"]["scale"] = 0.5; j["lights"][0]["intensity"] = 1e37; }, "shapes, lights", "emitted power past the float range"},
    {"no emitter", [](json& j) { j["shapes"][0]["emission"] = 0; j["lights"][0]["intensity"] = 0; }, "shapes, lights", "no emitter"},
};

class SceneErrorCase : public testing::TestWithParam<BadCase> {};

TEST_P(SceneErrorCase, NamesFileFieldAndProblem) {
  json scene = baseScene();
  GetParam().edit(scene);
  const std::string message = errorFor(scene.dump());
  ASSERT_FALSE(message.empty()) << "accepted: " << scene.dump();
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find(std::string(GetParam().field) + ":"), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().keyword), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Table, SceneErrorCase, testing::ValuesIn(kCases), test::tableCaseName<BadCase>);

TEST(SceneErrors, MeshErrorsAlsoNameTheGltfFile) {
  json scene = baseScene();
  scene["shapes"][1] = {{"type", "mesh"}, {"file", "points_mode.gltf"}};
  const std::string message = errorFor(scene.dump());
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find("points_mode.gltf"), std::string::npos) << message;
  EXPECT_NE(message.find("meshes[0].primitives[0].mode"), std::string::npos) << message;
}

TEST(SceneErrors, SyntaxErrorNamesTheLine) {
  const std::string message = errorFor("{\n  \"version\": 1,\n  \"camera\": {,\n}\n");
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find("syntax error"), std::string::npos) << message;
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
}

TEST(SceneErrors, OverflowingNumberIsRejected) {
  const std::string message = errorFor(R"({"version": 1e999})");
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find("malformed JSON"), std::string::npos) << message;
  EXPECT_NE(message.find("overflow"), std::string::npos) << message;
}

TEST(SceneErrors, DuplicateKeyIsRejected) {
  const std::string text = baseScene().dump();
  const std::string message = errorFor("{\"version\": 1, " + text.substr(1));
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find("version: duplicate field"), std::string::npos) << message;
}

TEST(SceneErrors, RootMustBeAnObject) {
  const std::string message = errorFor("[1, 2]");
  EXPECT_NE(message.find(kFile), std::string::npos) << message;
  EXPECT_NE(message.find("wrong type"), std::string::npos) << message;
}

std::string loadError(const fs::path& path) {
  try {
    loadScene(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

class SceneFileErrors : public testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() / ("vktg_scene_errors_" + std::to_string(::getpid()));
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  fs::path m_dir;
};

TEST_F(SceneFileErrors, MissingFile) {
  const fs::path path = m_dir / "absent.json";
  const std::string message = loadError(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("not found"), std::string::npos) << message;
}

TEST_F(SceneFileErrors, UnreadableFile) {
  // A directory with a scene's name cannot be read as a file (permission bits do not stop root).
  const fs::path path = m_dir / "folder.json";
  fs::create_directories(path);
  const std::string message = loadError(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("cannot read"), std::string::npos) << message;
}

TEST_F(SceneFileErrors, UnknownExtension) {
  const fs::path path = m_dir / "scene.yaml";
  std::ofstream(path) << "version: 1\n";
  const std::string message = loadError(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("extension"), std::string::npos) << message;
}

TEST_F(SceneFileErrors, MalformedJsonFileAndRelativeMeshPath) {
  const fs::path bad = m_dir / "broken.json";
  std::ofstream(bad) << "{\"version\": 1,, }";
  const std::string message = loadError(bad);
  EXPECT_NE(message.find(bad.string()), std::string::npos) << message;
  EXPECT_NE(message.find("malformed JSON"), std::string::npos) << message;

  // Mesh files resolve relative to the scene file's folder.
  json scene = baseScene();
  scene["shapes"][1] = {{"type", "mesh"}, {"file", "tiny.gltf"}};
  const fs::path good = m_dir / "mesh.json";
  std::ofstream(good) << scene.dump();
  const std::string relative = loadError(good);
  EXPECT_NE(relative.find((m_dir / "tiny.gltf").string()), std::string::npos) << relative;
  EXPECT_NE(relative.find("not found"), std::string::npos) << relative;
  fs::copy_file(kData / "tiny.gltf", m_dir / "tiny.gltf");
  EXPECT_EQ(loadError(good), "");
}

}  // namespace
}  // namespace vktg
