// glTF 2.0 input through tinygltf: whole scenes (loadGltfScene) and meshes placed by a JSON scene
// (appendGltfShapes). vktg renders geometry with scalar materials only, so textures are never
// decoded: tinygltf is built without stb_image and given an image loader that accepts and drops
// every image. This is the one translation unit that compiles tinygltf's implementation.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <set>

#include "scene/primitives.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kGltfDefaultHeight = 128;  // pixels; width follows the camera's aspect ratio
constexpr float kFramingFovY = 40.0f;         // degrees, for files without a camera

bool dropImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

double luminance(const std::vector<double>& rgb) {
  if (rgb.size() < 3) return 1.0;
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

// A loaded model plus the name errors use for it.
struct GltfFile {
  std::string name;
  tinygltf::Model model;

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    vktg::fail(name, field, problem);
  }
};

GltfFile loadModel(const fs::path& path) {
  GltfFile file{path.string(), {}};
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".gltf" && ext != ".glb") file.fail("", "unknown mesh file extension \"" + ext + "\" (expected .gltf or .glb)");
  std::error_code ec;
  if (!fs::exists(path, ec)) file.fail("", "file not found");
  if (!fs::is_regular_file(path, ec)) file.fail("", "cannot read: not a regular file");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(dropImage, nullptr);
  std::string err, warn;
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&file.model, &err, &warn, file.name)
                                : loader.LoadASCIIFromFile(&file.model, &err, &warn, file.name);
  if (!ok) file.fail("", "malformed glTF: " + oneLine(err.empty() ? "tinygltf could not load it" : err));
  return file;
}

// Checks that an accessor of the given type lies inside its buffer and returns its first byte
// and stride; tinygltf leaves these checks to the caller.
const unsigned char* accessorData(const GltfFile& file, int index, const std::string& field, int type,
                                  std::initializer_list<int> componentTypes, size_t& stride, size_t& elementSize) {
  const tinygltf::Model& model = file.model;
  if (index < 0 || size_t(index) >= model.accessors.size()) file.fail(field, "accessor index out of range");
  const std::string where = "accessors[" + std::to_string(index) + "]";
  const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
  if (accessor.sparse.isSparse) file.fail(where, "sparse accessors are not supported");
  if (accessor.type != type) file.fail(where, "wrong accessor type for " + field);
  if (std::find(componentTypes.begin(), componentTypes.end(), accessor.componentType) == componentTypes.end())
    file.fail(where, "unsupported componentType " + std::to_string(accessor.componentType) + " for " + field);
  if (accessor.bufferView < 0 || size_t(accessor.bufferView) >= model.bufferViews.size())
    file.fail(where, "bufferView index out of range");
  const tinygltf::BufferView& view = model.bufferViews[size_t(accessor.bufferView)];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    file.fail("bufferViews[" + std::to_string(accessor.bufferView) + "]", "buffer index out of range");
  const tinygltf::Buffer& buffer = model.buffers[size_t(view.buffer)];
  const int byteStride = accessor.ByteStride(view);
  if (byteStride <= 0) file.fail(where, "invalid byteStride");
  stride = size_t(byteStride);
  elementSize = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType))) *
                size_t(tinygltf::GetNumComponentsInType(uint32_t(accessor.type)));
  const size_t viewEnd = view.byteOffset + view.byteLength;
  const size_t begin = view.byteOffset + accessor.byteOffset;
  if (viewEnd > buffer.data.size() ||
      (accessor.count > 0 && begin + stride * (accessor.count - 1) + elementSize > viewEnd))
    file.fail(where, "data runs past the end of its buffer");
  return buffer.data.data() + begin;
}

// One triangles-mode primitive in the mesh's local frame.
TriangleMesh readPrimitive(const GltfFile& file, size_t meshIndex, size_t primIndex) {
  const tinygltf::Primitive& prim = file.model.meshes[meshIndex].primitives[primIndex];
  const std::string field = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primIndex) + "]";
  if (prim.mode != TINYGLTF_MODE_TRIANGLES)
    file.fail(field + ".mode", "unsupported primitive mode " + std::to_string(prim.mode) + " (only triangles, mode 4)");
  auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) file.fail(field + ".attributes", "missing required POSITION attribute");

  TriangleMesh mesh;
  size_t stride = 0, elementSize = 0;
  const unsigned char* data = accessorData(file, position->second, "POSITION", TINYGLTF_TYPE_VEC3,
                                           {TINYGLTF_COMPONENT_TYPE_FLOAT}, stride, elementSize);
  const size_t vertexCount = file.model.accessors[size_t(position->second)].count;
  mesh.positions.resize(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i) {
    float p[3];
    std::memcpy(p, data + i * stride, sizeof p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      file.fail(field + ".attributes.POSITION", "non-finite vertex position (NaN or infinity)");
    mesh.positions[i] = glm::vec3(p[0], p[1], p[2]);
  }

  std::vector<uint32_t> indices;
  if (prim.indices >= 0) {
    const unsigned char* idx = accessorData(file, prim.indices, "indices", TINYGLTF_TYPE_SCALAR,
                                            {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                                            stride, elementSize);
    const size_t count = file.model.accessors[size_t(prim.indices)].count;
    indices.resize(count);
    for (size_t i = 0; i < count; ++i) {
      const unsigned char* at = idx + i * stride;
      if (elementSize == 1) indices[i] = *at;
      if (elementSize == 2) { uint16_t v; std::memcpy(&v, at, 2); indices[i] = v; }
      if (elementSize == 4) std::memcpy(&indices[i], at, 4);
      if (indices[i] >= vertexCount) file.fail(field + ".indices", "vertex index " + std::to_string(indices[i]) + " out of range");
    }
  } else {
    indices.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) indices[i] = uint32_t(i);
  }
  if (indices.size() % 3 != 0)
    file.fail(field, "triangle list length " + std::to_string(indices.size()) + " is not a multiple of 3");
  for (size_t i = 0; i < indices.size(); i += 3) mesh.triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
  return mesh;
}

glm::mat4 nodeTransform(const tinygltf::Node& node) {
  glm::mat4 m(1.0f);
  if (node.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = float(node.matrix[size_t(c * 4 + r)]);  // glTF is column-major
    return m;
  }
  if (node.translation.size() == 3)
    m[3] = glm::vec4(float(node.translation[0]), float(node.translation[1]), float(node.translation[2]), 1.0f);
  glm::mat3 rs(1.0f);
  if (node.rotation.size() == 4) {
    // Unit quaternion (x, y, z, w) to a rotation matrix, written out to avoid depending on
    // glm's quaternion constructor argument order.
    const float x = float(node.rotation[0]), y = float(node.rotation[1]), z = float(node.rotation[2]),
                w = float(node.rotation[3]);
    rs = glm::mat3(1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),   // column 0
                   2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),   // column 1
                   2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y));  // column 2
  }
  if (node.scale.size() == 3) {
    rs[0] *= float(node.scale[0]);
    rs[1] *= float(node.scale[1]);
    rs[2] *= float(node.scale[2]);
  }
  for (int c = 0; c < 3; ++c) m[c] = glm::vec4(rs[c], 0.0f);
  return m;
}

// Calls visit(nodeIndex, worldTransform) for every node of the default scene, parents first.
void forEachNode(const GltfFile& file, const std::function<void(size_t, const glm::mat4&)>& visit) {
  const tinygltf::Model& model = file.model;
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(sceneIndex) >= model.scenes.size()) file.fail("scene", "default scene index out of range");
    roots = model.scenes[size_t(sceneIndex)].nodes;
  } else {
    // No scene list: every node that is nobody's child is a root.
    std::set<int> children;
    for (const tinygltf::Node& node : model.nodes) children.insert(node.children.begin(), node.children.end());
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!children.count(int(i))) roots.push_back(int(i));
  }
  std::function<void(int, const glm::mat4&, size_t)> walk = [&](int index, const glm::mat4& parent, size_t depth) {
    if (index < 0 || size_t(index) >= model.nodes.size()) file.fail("nodes", "node index " + std::to_string(index) + " out of range");
    if (depth > model.nodes.size()) file.fail("nodes", "the node hierarchy has a cycle");
    const tinygltf::Node& node = model.nodes[size_t(index)];
    const glm::mat4 world = parent * nodeTransform(node);
    visit(size_t(index), world);
    for (int child : node.children) walk(child, world, depth + 1);
  };
  for (int root : roots) walk(root, glm::mat4(1.0f), 0);
}

// Calls visit(mesh, meshIndex, primitiveIndex, worldTransform) for every primitive placed in the scene.
void forEachPrimitive(const GltfFile& file,
                      const std::function<void(TriangleMesh&, size_t, size_t, const glm::mat4&)>& visit) {
  forEachNode(file, [&](size_t nodeIndex, const glm::mat4& world) {
    const int meshIndex = file.model.nodes[nodeIndex].mesh;
    if (meshIndex < 0) return;
    if (size_t(meshIndex) >= file.model.meshes.size())
      file.fail("nodes[" + std::to_string(nodeIndex) + "].mesh", "mesh index out of range");
    const tinygltf::Mesh& mesh = file.model.meshes[size_t(meshIndex)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      TriangleMesh local = readPrimitive(file, size_t(meshIndex), p);
      transformMesh(local, world);
      if (!allFinite(local.positions))
        file.fail("nodes[" + std::to_string(nodeIndex) + "]",
                  "its transform (with its parents') takes vertex positions past the float range");
      visit(local, size_t(meshIndex), p, world);
    }
  });
}

double extensionNumber(const tinygltf::ExtensionMap& extensions, const std::string& extension, const std::string& key,
                       double fallback) {
  auto it = extensions.find(extension);
  if (it == extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tinygltf::Value& value = it->second.Get(key);
  return value.IsNumber() || value.IsInt() ? value.GetNumberAsDouble() : fallback;
}

Material convertMaterial(const GltfFile& file, size_t index, const std::string& name) {
  const tinygltf::Material& source = file.model.materials[index];
  const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
  Material material;
  material.name = name;
  material.albedo = float(std::clamp(luminance(pbr.baseColorFactor), 0.0, 1.0));
  // glTF's roughness is perceptual; GGX alpha is its square.
  material.roughness = float(std::clamp(pbr.roughnessFactor * pbr.roughnessFactor, 1e-3, 1.0));
  const double transmission = extensionNumber(source.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0);
  if (transmission > 0.5) {
    material.type = MaterialType::Dielectric;
    material.albedo = 1.0f;
    const double ior = extensionNumber(source.extensions, "KHR_materials_ior", "ior", 1.5);
    if (!(ior > 1.0) || !std::isfinite(ior))
      file.fail("materials[" + std::to_string(index) + "].extensions.KHR_materials_ior.ior",
                "out of range: a transmissive material needs ior > 1, got " + std::to_string(ior));
    material.ior = float(ior);
  } else if (pbr.metallicFactor > 0.5) {
    material.type = MaterialType::Conductor;
  } else {
    material.type = MaterialType::Diffuse;
  }
  return material;
}

float materialEmission(const GltfFile& file, int index) {
  if (index < 0) return 0.0f;
  const tinygltf::Material& m = file.model.materials[size_t(index)];
  const double strength = extensionNumber(m.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
  const double emission = luminance(m.emissiveFactor.size() == 3 ? m.emissiveFactor : std::vector<double>{0, 0, 0}) * strength;
  if (!std::isfinite(emission) || emission < 0)
    file.fail("materials[" + std::to_string(index) + "]", "out of range: emission must be finite and >= 0");
  return float(emission);
}

std::string uniqueName(std::set<std::string>& taken, const std::string& wanted) {
  std::string name = wanted;
  for (int k = 2; taken.count(name); ++k) name = wanted + "#" + std::to_string(k);
  taken.insert(name);
  return name;
}

Camera gltfCamera(const GltfFile& file, const tinygltf::Camera& source, size_t index, const glm::mat4& world) {
  const std::string field = "cameras[" + std::to_string(index) + "].perspective";
  const tinygltf::PerspectiveCamera& p = source.perspective;
  Camera camera;
  camera.type = CameraType::Perspective;
  camera.fovY = glm::degrees(float(p.yfov));
  if (!(camera.fovY > 0 && camera.fovY < 180)) file.fail(field + ".yfov", "out of range: must be in (0, pi) radians");
  camera.height = kGltfDefaultHeight;
  camera.width = p.aspectRatio > 0 ? std::max(1u, uint32_t(std::lround(kGltfDefaultHeight * p.aspectRatio)))
                                   : kGltfDefaultHeight;
  // A glTF camera looks down its local -z with +y up.
  camera.position = glm::vec3(world[3]);
  const glm::vec3 forward = glm::mat3(world) * glm::vec3(0, 0, -1);
  const glm::vec3 up = glm::mat3(world) * glm::vec3(0, 1, 0);
  if (glm::length(glm::cross(forward, up)) <= 0) file.fail("cameras[" + std::to_string(index) + "]", "degenerate camera node transform");
  camera.lookAt = camera.position + glm::normalize(forward);
  camera.up = glm::normalize(up);
  return camera;
}

// For files without a camera: look down -z at the centre of the bounds from far enough that a
// sphere around the bounds fits the field of view.
Camera framingCamera(const Scene& scene) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Shape& shape : scene.shapes)
    for (const glm::vec3& p : shape.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  for (const PointLight& light : scene.pointLights) {
    lo = glm::min(lo, light.position);
    hi = glm::max(hi, light.position);
  }
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  Camera camera;
  camera.type = CameraType::Perspective;
  camera.fovY = kFramingFovY;
  camera.width = camera.height = kGltfDefaultHeight;
  camera.lookAt = centre;
  camera.position = centre + glm::vec3(0, 0, radius / std::sin(glm::radians(0.5f * kFramingFovY)));
  camera.up = glm::vec3(0, 1, 0);
  return camera;
}

void readPointLight(const GltfFile& file, size_t nodeIndex, const glm::mat4& world, Scene& scene, std::set<std::string>& names) {
  const tinygltf::Node& node = file.model.nodes[nodeIndex];
  auto it = node.extensions.find("KHR_lights_punctual");
  if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("light")) return;
  const int index = it->second.Get("light").GetNumberAsInt();
  const std::string field = "lights[" + std::to_string(index) + "]";
  if (index < 0 || size_t(index) >= file.model.lights.size()) file.fail(field, "light index out of range");
  const tinygltf::Light& source = file.model.lights[size_t(index)];
  if (source.type != "point") file.fail(field + ".type", "unsupported light type \"" + source.type + "\" (only point lights)");
  PointLight light;
  light.name = uniqueName(names, source.name.empty() ? "light_" + std::to_string(index) : source.name);
  light.position = glm::vec3(world[3]);
  // Candela of a monochrome sensor: intensity times the luminance of the colour.
  light.intensity = float(source.intensity * luminance(source.color.empty() ? std::vector<double>{1, 1, 1} : source.color));
  if (!std::isfinite(light.intensity) || light.intensity < 0)
    file.fail(field + ".intensity", "out of range: must be finite and >= 0");
  scene.pointLights.push_back(light);
}

}  // namespace

void appendGltfShapes(Scene& scene, const std::filesystem::path& path, uint32_t defaultMaterial,
                      const glm::mat4& transform, float emission, const std::string& shapeName) {
  const GltfFile file = loadModel(path);
  // The JSON scene places the file as one shape: all primitives merged, one material.
  Shape shape;
  shape.name = shapeName;
  shape.material = defaultMaterial;
  shape.emission = emission;
  forEachPrimitive(file, [&](TriangleMesh& mesh, size_t, size_t, const glm::mat4&) {
    transformMesh(mesh, transform);
    const uint32_t base = uint32_t(shape.positions.size());
    shape.positions.insert(shape.positions.end(), mesh.positions.begin(), mesh.positions.end());
    for (const glm::uvec3& t : mesh.triangles) shape.triangles.push_back(t + base);
  });
  if (shape.triangles.empty()) file.fail("meshes", "empty mesh: the file places no triangles in its scene");
  scene.shapes.push_back(std::move(shape));
}

Scene loadGltfScene(const std::filesystem::path& path) {
  const GltfFile file = loadModel(path);
  Scene scene;
  scene.source = path;
  std::set<std::string> names;
  std::map<int, uint32_t> materials;  // glTF material index -> Scene::materials index
  auto materialIndex = [&](int gltfIndex) {
    if (gltfIndex >= int(file.model.materials.size())) file.fail("materials", "material index out of range");
    auto it = materials.find(gltfIndex);
    if (it != materials.end()) return it->second;
    Material material;
    if (gltfIndex < 0) {
      material = Material{"default", MaterialType::Diffuse, 0.8f};
    } else {
      const std::string& name = file.model.materials[size_t(gltfIndex)].name;
      material = convertMaterial(file, size_t(gltfIndex), name.empty() ? "material_" + std::to_string(gltfIndex) : name);
    }
    materials[gltfIndex] = uint32_t(scene.materials.size());
    scene.materials.push_back(material);
    return materials[gltfIndex];
  };

  forEachPrimitive(file, [&](TriangleMesh& mesh, size_t meshIndex, size_t primIndex, const glm::mat4&) {
    if (mesh.triangles.empty()) return;
    const tinygltf::Mesh& source = file.model.meshes[meshIndex];
    const tinygltf::Primitive& prim = source.primitives[primIndex];
    std::string name = source.name.empty() ? "mesh_" + std::to_string(meshIndex) : source.name;
    if (source.primitives.size() > 1) name += "/" + std::to_string(primIndex);
    Shape shape;
    shape.name = uniqueName(names, name);
    shape.material = materialIndex(prim.material);
    shape.emission = materialEmission(file, prim.material);
    shape.positions = std::move(mesh.positions);
    shape.triangles = std::move(mesh.triangles);
    scene.shapes.push_back(std::move(shape));
  });
  if (scene.shapes.empty()) file.fail("meshes", "empty: the file places no triangles in its scene");

  bool haveCamera = false;
  forEachNode(file, [&](size_t nodeIndex, const glm::mat4& world) {
    const tinygltf::Node& node = file.model.nodes[nodeIndex];
    readPointLight(file, nodeIndex, world, scene, names);
    if (haveCamera || node.camera < 0) return;
    if (size_t(node.camera) >= file.model.cameras.size())
      file.fail("nodes[" + std::to_string(nodeIndex) + "].camera", "camera index out of range");
    const tinygltf::Camera& camera = file.model.cameras[size_t(node.camera)];
    if (camera.type != "perspective") return;  // orthographic cameras are skipped (documented)
    scene.camera = gltfCamera(file, camera, size_t(node.camera), world);
    haveCamera = true;
  });
  if (!haveCamera) scene.camera = framingCamera(scene);
  scene.gate = Gate{};  // steady: a plain glTF carries no time gate
  if (!scene.hasEmitters())
    file.fail("materials", "no emitter: no mesh has an emissive material and no KHR_lights_punctual point light is placed");
  return scene;
}

}  // namespace vktg
