// The in-memory scene: what the parser produces and the renderer uploads. Units: metres,
// radiance in W sr^-1 m^-2, point-light intensity in W sr^-1, angles in degrees in files.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/gate.h"
#include "vktg/parameters.h"

namespace vktg {

enum class MaterialType : uint32_t { Diffuse = 0, Conductor = 1, Dielectric = 2 };

struct Material {
  std::string name;
  MaterialType type = MaterialType::Diffuse;
  float albedo = 0.8f;     // reflectance in [0, 1]
  float roughness = 0.2f;  // GGX alpha in [1e-3, 1] (conductor, dielectric)
  float ior = 1.5f;        // dielectric, > 1
};

// A triangle mesh in world space (transforms already applied).
struct Shape {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;  // indices into positions
  uint32_t material = 0;              // index into Scene::materials
  float emission = 0.0f;              // radiance emitted from the front face (winding order)
  glm::uvec2 grid{0u};                // a heightfield's (nx, nz): vertex j * nx + i at column i, row j; 0 otherwise
};

struct PointLight {
  std::string name;
  glm::vec3 position{0.0f};
  float intensity = 1.0f;  // W/sr, isotropic
};

enum class CameraType : uint32_t { Perspective = 0, PointSensor = 1 };

struct Camera {
  CameraType type = CameraType::Perspective;
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  glm::vec3 lookAt{0.0f};          // perspective
  glm::vec3 up{0.0f, 1.0f, 0.0f};  // perspective
  float fovY = 40.0f;              // degrees, perspective
  uint32_t width = 64, height = 64;  // perspective; a point sensor is 1x1
  glm::vec3 normal{0.0f, 0.0f, -1.0f};  // point sensor: cosine-weighted irradiance around this normal
};

// The film's size in pixels: width x height, or 1 x 1 for a point sensor.
inline glm::uvec2 imagePixels(const Camera& camera) {
  return camera.type == CameraType::PointSensor ? glm::uvec2(1u) : glm::uvec2(camera.width, camera.height);
}

enum class NeeMode : uint32_t { Auto = 0, Standard = 1, Ellipsoidal = 2, Mis = 3 };

struct RenderSettings {
  uint32_t spp = 16;
  uint32_t maxDepth = 16;      // vertices after the camera; gates usually end paths sooner
  uint32_t rouletteDepth = 4;  // Russian roulette from this depth on (where the gate allows)
  uint32_t seed = 0;
  NeeMode nee = NeeMode::Auto;
  bool operator==(const RenderSettings&) const = default;
};

struct Scene {
  std::filesystem::path source;  // file the scene came from (empty for the built-in default)
  std::vector<Material> materials;
  std::vector<Shape> shapes;
  std::vector<PointLight> pointLights;
  Camera camera;
  Gate gate;
  RenderSettings render;
  std::vector<Parameter> parameters;  // named scalars theta_k (vktg/parameters.h), 0 as written

  size_t triangleCount() const;
  bool hasEmitters() const;
  // Power emitted by all shapes (pi x emission x area) and point lights (4 pi x intensity), in
  // double: light selection is proportional to each one's share.
  double emittedPower() const;
};

// Values for the $name parameters of a Mitsuba XML scene (`-D name=value`), overriding its
// <default> elements.
using SceneDefines = std::map<std::string, std::string>;

// Loads a `.json` scene file, a plain `.gltf`/`.glb` or a Mitsuba 3 `.xml` scene (with `defines`;
// other formats take none). Throws vktg::Error ("file: field: problem", "file:line: ..." for XML).
Scene loadScene(const std::filesystem::path& path, const SceneDefines& defines = {});
// Parses scene JSON text; `file` names the source in errors, `baseDir` resolves relative paths.
Scene parseSceneJson(const std::string& text, const std::string& file, const std::filesystem::path& baseDir);
// Loads a glTF 2.0 file as a whole scene (meshes, materials, emissive meshes, first camera).
Scene loadGltfScene(const std::filesystem::path& path);
// Appends the meshes of a glTF file to `scene` as shapes (used by the JSON `mesh` shape).
void appendGltfShapes(Scene& scene, const std::filesystem::path& path, uint32_t defaultMaterial,
                      const glm::mat4& transform, float emission, const std::string& shapeName);
// The built-in default: a Cornell-box-like room seen by a box-gated ToF camera.
Scene defaultScene();
// Axis-aligned bounds of all shapes, lights and the camera.
void sceneBounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi);

}  // namespace vktg
