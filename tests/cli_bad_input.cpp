// Bad input to `vktg render`, one test per case (DESIGN.md §5). Every case must end the same way:
// a normal exit with a non-zero status (no signal, no hang), exactly one stderr line starting
// with "vktg: error: " that names the file or option, the field and the problem, and the working
// directory byte for byte as it was (no output created, no existing file changed).
#include <gtest/gtest.h>

#include <unistd.h>

#include <map>

#include <nlohmann/json.hpp>

#include "support/cli_runner.h"
#include "support/file_permissions.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Failing runs do no rendering; a generous bound still catches a hang quickly.
constexpr double kTimeoutSeconds = 120;

// A small valid scene: a floor lit by a ceiling lamp, box gate. Tests break one thing in it.
json baseScene() {
  return json::parse(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1, 3], "look_at": [0, 1, 0], "resolution": [8, 8]},
    "gate": {"type": "box", "a": 2, "b": 8},
    "materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "white", "transform": {"rotate": [-90, 0, 0]}},
      {"name": "lamp", "type": "rectangle", "material": "white", "emission": 5,
       "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0]}}
    ],
    "render": {"spp": 1}
  })");
}

class CliBadInput : public ::testing::Test {
 protected:
  fs::path writeScene(const json& scene, const std::string& name = "scene.json") {
    return writeText(scene.dump(2), name);
  }
  fs::path writeText(const std::string& text, const std::string& name) {
    writeFileBytes(m_dir / name, text);
    return m_dir / name;
  }
  fs::path copyFixture(const std::string& fixture, const std::string& name) {
    fs::copy_file(fs::path(VKTG_TEST_DATA) / fixture, m_dir / name);
    return m_dir / name;
  }
  std::string out() const { return (m_dir / "out.exr").string(); }

  // Runs `vktg ARGS` (with `env` added to the environment) in the temporary directory and checks
  // the failure contract; every string in `keywords` must appear in the one error line.
  void expectCleanFailure(const std::vector<std::string>& args, const std::vector<std::string>& keywords,
                          const std::map<std::string, std::string>& env = {}) {
    const auto before = directorySnapshot(m_dir);
    CliResult r = runVktg(args, {.env = env, .cwd = m_dir.path(), .timeoutSeconds = kTimeoutSeconds,
                                 .enforcePermissions = m_enforcePermissions});
    ASSERT_FALSE(r.timedOut) << "hang\n" << r.describe();
    ASSERT_TRUE(r.exited) << "crash\n" << r.describe();
    EXPECT_NE(r.exitCode, 0) << r.describe();
    std::vector<std::string> errors = linesStartingWith(r.err, "vktg: error: ");
    ASSERT_EQ(errors.size(), 1u) << "expected exactly one 'vktg: error: ' line\n" << r.describe();
    for (const std::string& word : keywords)
      EXPECT_NE(errors[0].find(word), std::string::npos) << "the error does not mention '" << word << "': " << errors[0];
    EXPECT_EQ(directorySnapshot(m_dir), before) << "the run created or changed files\n" << r.describe();
  }

  TempDir m_dir;
  bool m_enforcePermissions = false;  // run vktg without root's permission override
};

TEST_F(CliBadInput, BaseSceneIsValid) {
  // The control: the scene the other cases break renders, so their failures come from the break.
  fs::path scene = writeScene(baseScene());
  CliResult r = runVktg({"render", scene.string(), "--quiet", "--out", out()}, {.cwd = m_dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_TRUE(fs::is_regular_file(out()));
}

TEST_F(CliBadInput, MissingSceneFile) {
  expectCleanFailure({"render", (m_dir / "nowhere.json").string(), "--out", out()}, {"nowhere.json", "not found"});
}

TEST_F(CliBadInput, UnreadableSceneFile) {
  if (!canDropFileOverrideForExec()) GTEST_SKIP() << "running as root without CAP_SETPCAP: cannot enforce permissions";
  m_enforcePermissions = true;
  fs::path scene = writeScene(baseScene());
  fs::permissions(scene, fs::perms::none);
  expectCleanFailure({"render", scene.string(), "--out", out()}, {"scene.json", "cannot read"});
}

TEST_F(CliBadInput, SceneIsADirectory) {
  fs::create_directory(m_dir / "dir.json");
  expectCleanFailure({"render", (m_dir / "dir.json").string(), "--out", out()}, {"dir.json", "not a regular file"});
}

TEST_F(CliBadInput, MalformedJson) {
  fs::path scene = writeText("{\"version\": 1, \"camera\": {\"type\": \"perspective\",", "scene.json");
  expectCleanFailure({"render", scene.string(), "--out", out()}, {"scene.json", "malformed JSON"});
}

TEST_F(CliBadInput, UnknownSceneExtension) {
  fs::path scene = writeScene(baseScene(), "scene.txt");
  expectCleanFailure({"render", scene.string(), "--out", out()}, {"scene.txt", "extension"});
}

TEST_F(CliBadInput, UnknownFieldIsATypo) {
  json scene = baseScene();
  scene["camera"]["fov"] = 40;  // the field is fov_y
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "camera.fov", "unknown field"});
}

TEST_F(CliBadInput, UnknownTopLevelField) {
  json scene = baseScene();
  scene["light"] = json::array();  // the field is lights
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "light", "unknown field"});
}

TEST_F(CliBadInput, WrongTypeString) {
  json scene = baseScene();
  scene["render"]["spp"] = "many";
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "render.spp", "wrong type"});
}

TEST_F(CliBadInput, WrongTypeVector) {
  json scene = baseScene();
  scene["camera"]["position"] = 3;
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"camera.position", "wrong type"});
}

TEST_F(CliBadInput, NanAsStringAlbedo) {
  json scene = baseScene();
  scene["materials"]["white"]["albedo"] = "nan";
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"albedo", "wrong type"});
}

TEST_F(CliBadInput, NanAsStringGateLength) {
  // Gate lengths accept strings ("12ns"), so "nan" gets through the type check and must be
  // caught as a value.
  json scene = baseScene();
  scene["gate"]["a"] = "nan";
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"gate.a", "nan"});
}

TEST_F(CliBadInput, OverflowingNumber) {
  json scene = baseScene();
  scene["shapes"][1]["emission"] = 123.25;
  std::string text = scene.dump(2);
  text.replace(text.find("123.25"), 6, "1e999");
  expectCleanFailure({"render", writeText(text, "scene.json").string(), "--out", out()}, {"scene.json", "1e999"});
}

TEST_F(CliBadInput, NegativeEmission) {
  json scene = baseScene();
  scene["shapes"][1]["emission"] = -5;
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"emission", "out of range"});
}

TEST_F(CliBadInput, NegativeAlbedo) {
  json scene = baseScene();
  scene["materials"]["white"]["albedo"] = -0.5;
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"albedo", "out of range"});
}

TEST_F(CliBadInput, NegativePointLightIntensity) {
  json scene = baseScene();
  scene["lights"] = json::parse(R"([{"type": "point", "position": [0, 1, 0], "intensity": -1}])");
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"intensity", "out of range"});
}

TEST_F(CliBadInput, NegativeGateSigma) {
  json scene = baseScene();
  scene["gate"] = json::parse(R"({"type": "gaussian", "mu": 4, "sigma": -0.1})");
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"gate", "sigma"});
}

TEST_F(CliBadInput, NegativeGateStart) {
  json scene = baseScene();
  scene["gate"] = json::parse(R"({"type": "box", "a": -1, "b": 3})");
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"gate", "a must be >= 0"});
}

TEST_F(CliBadInput, ZeroResolution) {
  json scene = baseScene();
  scene["camera"]["resolution"] = json::array({0, 8});
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"camera.resolution", "out of range"});
}

TEST_F(CliBadInput, NegativeFieldOfView) {
  json scene = baseScene();
  scene["camera"]["fov_y"] = -30;
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"fov_y", "out of range"});
}

TEST_F(CliBadInput, EmptyMeshInScene) {
  copyFixture("no_meshes.gltf", "empty.gltf");
  json scene = baseScene();
  scene["shapes"].push_back(json::parse(R"({"name": "nothing", "type": "mesh", "file": "empty.gltf"})"));
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "empty.gltf", "empty"});
}

TEST_F(CliBadInput, EmptyGltfRenderedDirectly) {
  fs::path gltf = copyFixture("no_meshes.gltf", "empty.gltf");
  expectCleanFailure({"render", gltf.string(), "--out", out()}, {"empty.gltf", "empty"});
}

TEST_F(CliBadInput, MissingMeshFile) {
  json scene = baseScene();
  scene["shapes"].push_back(json::parse(R"({"name": "ghost", "type": "mesh", "file": "ghost.gltf"})"));
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"ghost.gltf", "not found"});
}

TEST_F(CliBadInput, GateAAboveBInSceneFile) {
  json scene = baseScene();
  scene["gate"] = json::parse(R"({"type": "box", "a": 5, "b": 3})");
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "gate", "a must be < b"});
}

TEST_F(CliBadInput, TruncatedGaussianAAboveBInSceneFile) {
  json scene = baseScene();
  scene["gate"] = json::parse(R"({"type": "truncated_gaussian", "mu": 4, "sigma": 0.5, "a": 5, "b": 3})");
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "gate", "a must be < b"});
}

TEST_F(CliBadInput, GateAAboveBOnCommandLine) {
  expectCleanFailure({"render", "--gate", "box:5,3", "--out", out()}, {"--gate", "a must be < b"});
}

// Malformed --gate specs: each must be rejected naming --gate (never an exception's raw text).
class CliBadGateSpec : public CliBadInput, public ::testing::WithParamInterface<std::pair<std::string, std::string>> {};

TEST_P(CliBadGateSpec, IsRejected) {
  expectCleanFailure({"render", "--gate", GetParam().second, "--out", out()}, {"--gate"});
}

INSTANTIATE_TEST_SUITE_P(Cases, CliBadGateSpec,
                         ::testing::Values(std::pair<std::string, std::string>{"MissingNumber", "box:3"},
                                           std::pair<std::string, std::string>{"ExtraNumber", "box:3,4,5"},
                                           std::pair<std::string, std::string>{"UnknownKind", "gauss:4,0.1"},
                                           std::pair<std::string, std::string>{"NotANumber", "box:x,5"},
                                           std::pair<std::string, std::string>{"TrailingJunk", "box:3,5q"},
                                           std::pair<std::string, std::string>{"Semicolon", "box:3;5"},
                                           std::pair<std::string, std::string>{"Empty", ""},
                                           std::pair<std::string, std::string>{"ZeroSigma", "gaussian:4,0"},
                                           std::pair<std::string, std::string>{"InfiniteMu", "gaussian:inf,0.1"},
                                           std::pair<std::string, std::string>{"BinCountWord", "bins:3,0.5,many"},
                                           std::pair<std::string, std::string>{"BinCountFraction", "bins:3,0.5,2.5"},
                                           std::pair<std::string, std::string>{"BinCountZero", "bins:3,0.5,0"},
                                           std::pair<std::string, std::string>{"SteadyWithArgs", "steady:1"}),
                         [](const auto& info) { return info.param.first; });

TEST_F(CliBadInput, UnknownOption) {
  expectCleanFailure({"render", "--sppp", "2", "--out", out()}, {"--sppp", "unknown option"});
}

TEST_F(CliBadInput, OptionWithoutValue) {
  expectCleanFailure({"render", "--out", out(), "--spp"}, {"--spp", "value"});
}

TEST_F(CliBadInput, UnknownCommand) {
  expectCleanFailure({"rendr"}, {"rendr", "unknown command"});
}

class CliBadSpp : public CliBadInput, public ::testing::WithParamInterface<std::pair<std::string, std::string>> {};

TEST_P(CliBadSpp, IsRejected) {
  expectCleanFailure({"render", "--spp", GetParam().second, "--out", out()}, {"--spp", GetParam().second});
}

INSTANTIATE_TEST_SUITE_P(Cases, CliBadSpp,
                         ::testing::Values(std::pair<std::string, std::string>{"Zero", "0"},
                                           std::pair<std::string, std::string>{"Negative", "-4"},
                                           std::pair<std::string, std::string>{"Word", "many"},
                                           std::pair<std::string, std::string>{"Fraction", "2.5"},
                                           std::pair<std::string, std::string>{"TooLarge", "99999999999"}),
                         [](const auto& info) { return info.param.first; });

TEST_F(CliBadInput, BadResolution) {
  expectCleanFailure({"render", "--resolution", "16by16", "--out", out()}, {"--resolution", "16by16"});
}

TEST_F(CliBadInput, MalformedGltf) {
  fs::path gltf = copyFixture("malformed.gltf", "broken.gltf");
  expectCleanFailure({"render", gltf.string(), "--out", out()}, {"broken.gltf", "malformed glTF"});
}

TEST_F(CliBadInput, GltfAccessorPastItsBuffer) {
  fs::path gltf = copyFixture("accessor_overrun.gltf", "overrun.gltf");
  expectCleanFailure({"render", gltf.string(), "--out", out()}, {"overrun.gltf", "past the end"});
}

TEST_F(CliBadInput, TruncatedGlb) {
  const std::string bytes = readFileBytes(fs::path(VKTG_TEST_DATA) / "tiny.glb");
  fs::path glb = writeText(bytes.substr(0, bytes.size() / 2), "truncated.glb");
  expectCleanFailure({"render", glb.string(), "--out", out()}, {"truncated.glb", "glTF"});
}

TEST_F(CliBadInput, MalformedGltfReferencedFromScene) {
  copyFixture("malformed.gltf", "broken.gltf");
  json scene = baseScene();
  scene["shapes"].push_back(json::parse(R"({"name": "broken", "type": "mesh", "file": "broken.gltf"})"));
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()}, {"scene.json", "broken.gltf", "malformed glTF"});
}

TEST_F(CliBadInput, OutInMissingDirectory) {
  expectCleanFailure({"render", "--out", (m_dir / "missing" / "out.exr").string()}, {"missing", "does not exist"});
}

TEST_F(CliBadInput, OutIsTheSceneFile) {
  fs::path scene = writeScene(baseScene());
  expectCleanFailure({"render", scene.string(), "--out", scene.string()}, {"--out", "scene.json"});
}

TEST_F(CliBadInput, OutIsALinkToTheSceneFile) {
  // Passes the extension check, so only the same-file check protects the input.
  fs::path scene = writeScene(baseScene());
  fs::create_symlink(scene, m_dir / "alias.exr");
  expectCleanFailure({"render", scene.string(), "--out", (m_dir / "alias.exr").string()},
                     {"alias.exr", "overwrite", "scene.json"});
}

TEST_F(CliBadInput, OutWithoutExrExtension) {
  expectCleanFailure({"render", "--out", (m_dir / "image.png").string()}, {"--out", "image.png", ".exr"});
}

// The variables that force a device's choices (docs/robustness.md) name themselves when misspelt.
TEST_F(CliBadInput, UnknownBvhWidth) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_BVH_WIDTH", "'3'"}, {{"VKTG_BVH_WIDTH", "3"}});
}

// On a GPU the scene is read from storage buffers and the wide tree is never built; the variable
// is still checked (it once went unread there, and the bad value was silently ignored).
TEST_F(CliBadInput, UnknownBvhWidthWhereTheWideTreeIsNotUsed) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_BVH_WIDTH", "'3'"},
                     {{"VKTG_BVH_WIDTH", "3"}, {"VKTG_SCENE_ACCESS", "storage"}});
}

TEST_F(CliBadInput, UnknownSceneAccess) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_SCENE_ACCESS", "'stream'"},
                     {{"VKTG_SCENE_ACCESS", "stream"}});
}

TEST_F(CliBadInput, UnknownShadowSlots) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_SHADOW_SLOTS", "'some'"},
                     {{"VKTG_SHADOW_SLOTS", "some"}});
}

// Read by every render, edges or not.
TEST_F(CliBadInput, UnknownEdgeDispatch) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_EDGE_DISPATCH", "'apart'"},
                     {{"VKTG_EDGE_DISPATCH", "apart"}});
}

// Read by every render, boundary terms or not.
TEST_F(CliBadInput, UnknownBoundarySamples) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_BOUNDARY_SAMPLES", "'sobol'"},
                     {{"VKTG_BOUNDARY_SAMPLES", "sobol"}});
}

TEST_F(CliBadInput, UnknownPipelineCreation) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_PIPELINE_CREATION", "'threads'"},
                     {{"VKTG_PIPELINE_CREATION", "threads"}});
}

TEST_F(CliBadInput, UnknownDeviceMemory) {
  expectCleanFailure({"render", "--spp", "1", "--out", out()}, {"VKTG_DEVICE_MEMORY", "'host'"},
                     {{"VKTG_DEVICE_MEMORY", "host"}});
}

TEST_F(CliBadInput, OutIsADirectory) {
  fs::create_directory(m_dir / "taken.exr");
  expectCleanFailure({"render", "--out", (m_dir / "taken.exr").string()}, {"taken.exr", "directory"});
}

TEST_F(CliBadInput, ExistingOutputsSurviveABadScene) {
  // Sentinels where the EXR and the PNG would go; the snapshot check proves them unchanged.
  writeText("sentinel exr bytes", "out.exr");
  writeText("sentinel png bytes", "out.png");
  fs::path scene = writeText("{\"version\": 1,,}", "scene.json");
  expectCleanFailure({"render", scene.string(), "--out", out()}, {"scene.json", "malformed JSON"});
}

TEST_F(CliBadInput, ExistingOutputsSurviveAFailureAfterDeviceSetup) {
  // This failure comes from the planner, after the output checks and the Vulkan context.
  writeText("sentinel exr bytes", "out.exr");
  writeText("sentinel png bytes", "out.png");
  writeText("sentinel npy bytes", "out.npy");
  expectCleanFailure({"render", "--gate", "steady", "--nee", "ellipsoidal", "--npy", "--out", out()}, {"--nee", "steady"});
}

TEST_F(CliBadInput, EllipsoidalNeeWithSteadyGate) {
  expectCleanFailure({"render", "--gate", "steady", "--nee", "ellipsoidal", "--spp", "1", "--out", out()},
                     {"--nee", "ellipsoidal", "steady"});
}

TEST_F(CliBadInput, EllipsoidalNeeWithSteadyGateFromSceneFile) {
  json scene = baseScene();
  scene["gate"] = json::parse(R"({"type": "steady"})");
  scene["render"]["nee"] = "ellipsoidal";
  expectCleanFailure({"render", writeScene(scene).string(), "--out", out()},
                     {"scene.json", "render.nee", "ellipsoidal", "steady"});
}

TEST_F(CliBadInput, UnknownNeeMode) {
  expectCleanFailure({"render", "--nee", "fast", "--out", out()}, {"--nee", "fast"});
}

}  // namespace
}  // namespace vktg::test

namespace vktg::test {

// EXR inputs (`vktg inspect` reads outputs back): missing, empty, garbage and truncated files.
TEST_F(CliBadInput, MissingExr) {
  expectCleanFailure({"inspect", (m_dir / "nowhere.exr").string()}, {"nowhere.exr"});
}

TEST_F(CliBadInput, GarbageExr) {
  fs::path exr = m_dir / "garbage.exr";
  writeFileBytes(exr, "this is not an OpenEXR file\n");
  expectCleanFailure({"inspect", exr.string()}, {"garbage.exr", "OpenEXR"});
}

TEST_F(CliBadInput, TruncatedExr) {
  // A real output cut in half.
  fs::path scene = writeScene(baseScene());
  fs::path whole = m_dir / "whole.exr";
  CliResult r = runVktg({"render", scene.string(), "--quiet", "--spp", "1", "--out", whole.string()}, {.cwd = m_dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  std::string bytes = readFileBytes(whole);
  fs::path cut = m_dir / "cut.exr";
  writeFileBytes(cut, bytes.substr(0, bytes.size() / 2));
  expectCleanFailure({"inspect", cut.string()}, {"cut.exr"});
}

}  // namespace vktg::test
