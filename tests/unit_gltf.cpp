// glTF input: a small hand-made file (tests/data/tiny.gltf, embedded base64 buffer, and the same
// model as tiny.glb) with two meshes, node transforms, two materials and a camera; malformed files.
//
// tiny.gltf: node "floor" places mesh "quad" (square [-1,1]^2 at z = 0, 2 indexed triangles,
// material "grey": baseColor 0.5, not metallic) at z = -1; node "lamp" places mesh "lamp" (one
// non-indexed triangle (-0.5,0,0), (0.5,0,0), (0,0.5,0), material "emitter": metallic, roughness
// 0.5, emissive [1,1,1] with KHR_materials_emissive_strength 5) rotated +90 degrees about x and
// moved to y = 2; node "cam" places a perspective camera (yfov 30 degrees, aspect 1.5) at z = 5.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "scene/primitives.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
const fs::path kData = VKTG_TEST_DATA;

void expectNear(glm::vec3 a, glm::vec3 b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

glm::vec3 normalOf(const Shape& s, size_t i) {
  const glm::uvec3 t = s.triangles[i];
  return glm::normalize(glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]));
}

void expectTinyScene(const Scene& scene) {
  EXPECT_EQ(scene.triangleCount(), 3u);
  ASSERT_EQ(scene.shapes.size(), 2u);
  const Shape& quad = scene.shapes[0];
  const Shape& lamp = scene.shapes[1];
  EXPECT_EQ(quad.name, "quad");
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(quad.triangles.size(), 2u);
  EXPECT_NEAR(meshArea(quad.positions, quad.triangles), 4.0, 1e-6);
  for (const glm::vec3& p : quad.positions) EXPECT_FLOAT_EQ(p.z, -1.0f);
  for (size_t i = 0; i < quad.triangles.size(); ++i) expectNear(normalOf(quad, i), {0, 0, 1});
  // Rotating +90 degrees about x takes (x, y, 0) to (x, 0, y); the normal +z goes to -y.
  expectNear(lamp.positions[0], {-0.5f, 2, 0});
  expectNear(lamp.positions[2], {0, 2, 0.5f});
  expectNear(normalOf(lamp, 0), {0, -1, 0});

  const Material& grey = scene.materials[quad.material];
  EXPECT_EQ(grey.name, "grey");
  EXPECT_EQ(grey.type, MaterialType::Diffuse);
  EXPECT_NEAR(grey.albedo, 0.5f, 1e-6f);
  EXPECT_EQ(quad.emission, 0.0f);
  const Material& emitter = scene.materials[lamp.material];
  EXPECT_EQ(emitter.type, MaterialType::Conductor);
  EXPECT_NEAR(emitter.albedo, 1.0f, 1e-6f);
  EXPECT_NEAR(emitter.roughness, 0.25f, 1e-6f);  // roughnessFactor^2
  EXPECT_NEAR(lamp.emission, 5.0f, 1e-5f);       // luminance(1,1,1) * strength 5

  EXPECT_EQ(scene.camera.type, CameraType::Perspective);
  expectNear(scene.camera.position, {0, 0, 5});
  expectNear(glm::normalize(scene.camera.lookAt - scene.camera.position), {0, 0, -1});
  expectNear(scene.camera.up, {0, 1, 0});
  EXPECT_NEAR(scene.camera.fovY, 30.0f, 1e-4f);
  EXPECT_EQ(scene.camera.height, 128u);
  EXPECT_EQ(scene.camera.width, 192u);
  EXPECT_EQ(scene.gate.type, GateType::Steady);
  EXPECT_TRUE(scene.hasEmitters());
}

TEST(Gltf, TinyGltfLoads) {
  const Scene scene = loadGltfScene(kData / "tiny.gltf");
  EXPECT_EQ(scene.source, kData / "tiny.gltf");
  expectTinyScene(scene);
}

TEST(Gltf, TinyGlbLoadsTheSame) { expectTinyScene(loadGltfScene(kData / "tiny.glb")); }

TEST(Gltf, LoadSceneDispatchesOnExtension) { expectTinyScene(loadScene(kData / "tiny.gltf")); }

TEST(Gltf, FileWithoutCameraGetsOneFramingItsBounds) {
  const Scene scene = loadGltfScene(kData / "no_camera.gltf");  // triangle (0,0,0), (2,0,0), (0,2,0)
  ASSERT_EQ(scene.triangleCount(), 1u);
  expectNear(scene.camera.lookAt, {1, 1, 0});
  // The bounding sphere (radius sqrt(2)) must fit inside the vertical field of view.
  const float distance = glm::distance(scene.camera.position, scene.camera.lookAt);
  EXPECT_LE(std::asin(std::sqrt(2.0f) / distance), glm::radians(0.5f * scene.camera.fovY) + 1e-6f);
  EXPECT_GT(scene.camera.position.z, 0.0f);  // in front of the triangle's front face (+z)
}

TEST(Gltf, AppendPlacesAllPrimitivesAsOneShape) {
  Scene scene;
  scene.materials.push_back(Material{"mine", MaterialType::Diffuse, 0.3f});
  const glm::mat4 transform = composeTransform({0, 0, 1}, {0, 0, 0}, glm::vec3(2));
  appendGltfShapes(scene, kData / "tiny.gltf", 0, transform, 7.0f, "thing");
  ASSERT_EQ(scene.shapes.size(), 1u);
  const Shape& s = scene.shapes[0];
  EXPECT_EQ(s.name, "thing");
  EXPECT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.material, 0u);
  EXPECT_EQ(s.emission, 7.0f);
  EXPECT_EQ(scene.materials.size(), 1u);  // the file's materials are not imported
  EXPECT_TRUE(scene.pointLights.empty());
  // Quad corner (-1,-1,0) -> node z = -1 -> scaled by 2 -> z = -2 -> moved to z = -1.
  expectNear(s.positions[0], {-2, -2, -1});
  EXPECT_NEAR(meshArea(s.positions, s.triangles), 4.0 * (4.0 + 0.25), 1e-5);
  for (const glm::uvec3& t : s.triangles)
    for (int k = 0; k < 3; ++k) EXPECT_LT(t[k], s.positions.size());
}

std::string gltfError(const std::string& name) {
  try {
    loadGltfScene(kData / name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

struct BadGltf {
  const char* file;
  const char* field;
  const char* keyword;
};

class GltfErrors : public testing::TestWithParam<BadGltf> {};

TEST_P(GltfErrors, NameFileAndProblem) {
  const std::string message = gltfError(GetParam().file);
  ASSERT_FALSE(message.empty());
  EXPECT_NE(message.find((kData / GetParam().file).string()), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().field), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().keyword), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Files, GltfErrors,
                         testing::Values(BadGltf{"malformed.gltf", "", "malformed glTF"},
                                         BadGltf{"missing.gltf", "", "not found"},
                                         BadGltf{"points_mode.gltf", "meshes[0].primitives[0].mode", "unsupported primitive mode"},
                                         BadGltf{"accessor_overrun.gltf", "accessors[0]", "past the end"},
                                         BadGltf{"no_emitter.gltf", "materials", "no emitter"},
                                         BadGltf{"no_meshes.gltf", "meshes", "empty"},
                                         // Found by fuzzing: a node whose unnormalised rotation scales a vertex at
                                         // 3.8e22 m past the float range (the BVH build then binned a NaN).
                                         BadGltf{"transform_overflow.glb", "nodes[1]", "past the float range"}),
                         [](const testing::TestParamInfo<BadGltf>& info) {
                           std::string name = info.param.file;
                           return name.substr(0, name.find('.'));
                         });

TEST(Gltf, WrongExtensionForMeshFile) {
  Scene scene;
  try {
    appendGltfShapes(scene, kData / "tiny.obj", 0, glm::mat4(1.0f), 0.0f, "x");
    FAIL() << "accepted an .obj";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tiny.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("extension"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vktg
