// The JSON scene format (docs/scene-format.md): strict parsing into vktg::Scene, and loadScene,
// which dispatches on the file extension (as a mesh shape's `file` does).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "scene/mesh_files.h"
#include "scene/mitsuba_xml.h"
#include "scene/primitives.h"
#include "scene/scene_values.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kSceneVersion = 1;
constexpr uint32_t kMaxResolution = 16384;
constexpr uint32_t kMaxSphereSubdivisions = 8;  // 20 * 4^8 = 1.3M triangles
constexpr uint32_t kMaxHeightfieldResolution = 4096;

class SceneParser {
 public:
  SceneParser(std::string file, fs::path baseDir) : m_file(std::move(file)), m_baseDir(std::move(baseDir)) {}

  // Parameters given outside a scene's own file (an experiment's, for a scene format that has none)
  // bind to `scene`'s shapes, lights and materials as a JSON scene's own would.
  Scene addParameters(Scene scene, const JsonValue& parameters) {
    m_file = parameters.file;
    m_scene = std::move(scene);
    for (size_t m = 0; m < m_scene.materials.size(); ++m) m_materials.emplace(m_scene.materials[m].name, uint32_t(m));
    for (const Parameter& p : m_scene.parameters) m_parameterNames.insert(p.name);
    for (size_t i = 0; i < parameters.array().size(); ++i) parseParameter(parameters.element(i));
    applyValues();
    return std::move(m_scene);
  }

  Scene parse(const Json& json) {
    m_scene.source = m_file;
    const JsonObject root(JsonValue{&json, m_file, ""},
                          {"version", "description", "camera", "gate", "materials", "shapes", "lights", "render",
                           "parameters"});
    const JsonValue version = root.field("version");
    const uint32_t v = version.uinteger(0, std::numeric_limits<uint32_t>::max());
    if (v != kSceneVersion)
      version.fail("unsupported version " + std::to_string(v) + " (this vktg reads version " +
                   std::to_string(kSceneVersion) + ")");
    if (root.has("description")) root.field("description").string();
    parseCamera(root.field("camera"));
    if (root.has("gate")) m_scene.gate = parseGateValue(root.field("gate"));
    if (root.has("materials")) parseMaterials(root.field("materials"));
    if (root.has("shapes")) {
      const JsonValue shapes = root.field("shapes");
      for (size_t i = 0; i < shapes.array().size(); ++i) parseShape(shapes.element(i));
    }
    if (root.has("lights")) {
      const JsonValue lights = root.field("lights");
      for (size_t i = 0; i < lights.array().size(); ++i) parseLight(lights.element(i));
    }
    if (root.has("render")) parseRender(root.field("render"));
    if (!m_scene.hasEmitters())
      fail(m_file, "shapes, lights",
           "no emitter: the scene needs a shape with emission > 0 or a point light with intensity > 0");
    if (!(m_scene.emittedPower() <= double(std::numeric_limits<float>::max())))
      fail(m_file, "shapes, lights", "emitted power past the float range: the emitters' power summed exceeds it");
    // Last: parameters refer to shapes, lights, materials and the gate, and check how they are used.
    if (root.has("parameters")) {
      const JsonValue parameters = root.field("parameters");
      for (size_t i = 0; i < parameters.array().size(); ++i) parseParameter(parameters.element(i));
      applyValues();
    }
    return std::move(m_scene);
  }

 private:
  void parseCamera(const JsonValue& value) {
    Camera& camera = m_scene.camera;
    if (typeOf(value, {"perspective", "point_sensor"}) == "perspective") {
      const JsonObject o(value, {"type", "position", "look_at", "up", "fov_y", "resolution"});
      camera.type = CameraType::Perspective;
      camera.position = o.field("position").vec3();
      camera.lookAt = o.field("look_at").vec3();
      camera.up = o.vec3("up", glm::vec3(0, 1, 0));
      camera.fovY = float(o.number("fov_y", 40.0));
      if (!(camera.fovY > 0 && camera.fovY < 180))
        o.field("fov_y").fail("out of range: " + formatNumber(camera.fovY) + " degrees is not in (0, 180)");
      if (o.has("resolution")) {
        const JsonValue res = o.field("resolution");
        if (!res.json().is_array() || res.json().size() != 2)
          res.fail("wrong type: expected [width, height] (2 integers)");
        camera.width = res.element(0).uinteger(1, kMaxResolution);
        camera.height = res.element(1).uinteger(1, kMaxResolution);
      }
      const glm::vec3 dir = camera.lookAt - camera.position;
      if (glm::length(dir) <= 0) o.field("look_at").fail("degenerate camera: look_at equals position");
      if (glm::length(camera.up) <= 0) o.field("up").fail("degenerate camera: up must not be zero");
      if (glm::length(glm::cross(glm::normalize(dir), glm::normalize(camera.up))) < 1e-6f)
        o.field("up").fail("degenerate camera: up is parallel to the view direction");
      camera.up = glm::normalize(camera.up);
    } else {
      const JsonObject o(value, {"type", "position", "normal"});
      camera.type = CameraType::PointSensor;
      camera.position = o.field("position").vec3();
      const glm::vec3 normal = o.field("normal").vec3();
      if (glm::length(normal) <= 0) o.field("normal").fail("degenerate camera: normal must not be zero");
      camera.normal = glm::normalize(normal);
      camera.width = camera.height = 1;
    }
  }

  void parseMaterials(const JsonValue& value) {
    if (!value.json().is_object()) value.fail("wrong type: expected an object mapping names to materials");
    for (const auto& item : value.json().items()) {
      const JsonValue entry{&item.value(), m_file, value.path + "." + item.key()};
      Material material;
      material.name = item.key();
      const std::string type = typeOf(entry, {"diffuse", "conductor", "dielectric"});
      if (type == "diffuse") {
        const JsonObject o(entry, {"type", "albedo"});
        material.type = MaterialType::Diffuse;
        material.albedo = readAlbedo(o);
      } else if (type == "conductor") {
        const JsonObject o(entry, {"type", "albedo", "roughness"});
        material.type = MaterialType::Conductor;
        material.albedo = readAlbedo(o);
        material.roughness = readRoughness(o);
      } else {
        const JsonObject o(entry, {"type", "roughness", "ior"});
        material.type = MaterialType::Dielectric;
        material.albedo = 1.0f;  // a dielectric loses no energy; Fresnel splits reflection and refraction
        material.roughness = readRoughness(o);
        material.ior = float(o.number("ior", 1.5));
        if (o.has("ior")) requireAbove(o.field("ior"), material.ior, 1.0);
      }
      m_materials[material.name] = uint32_t(m_scene.materials.size());
      m_scene.materials.push_back(material);
    }
  }

  static float readAlbedo(const JsonObject& o) {
    const double albedo = o.number("albedo", 0.8);
    if (o.has("albedo")) requireInRange(o.field("albedo"), albedo, 0.0, 1.0);
    return float(albedo);
  }

  static float readRoughness(const JsonObject& o) {
    const double roughness = o.number("roughness", 0.2);
    if (o.has("roughness")) requireInRange(o.field("roughness"), roughness, 1e-3, 1.0);
    return float(roughness);
  }

  uint32_t materialFor(const JsonObject& o) {
    if (o.has("material")) {
      const JsonValue field = o.field("material");
      const std::string name = field.string();
      auto it = m_materials.find(name);
      if (it == m_materials.end()) field.fail("unknown material \"" + name + "\" (not defined in \"materials\")");
      return it->second;
    }
    auto it = m_materials.find("default");
    if (it != m_materials.end()) return it->second;
    m_materials["default"] = uint32_t(m_scene.materials.size());
    m_scene.materials.push_back(Material{"default", MaterialType::Diffuse, 0.8f});
    return m_materials["default"];
  }

  glm::mat4 parseTransform(const JsonObject& shape) {
    if (!shape.has("transform")) return glm::mat4(1.0f);
    const JsonObject o(shape.field("transform"), {"translate", "rotate", "scale"});
    glm::vec3 scale(1.0f);
    if (o.has("scale")) {
      const JsonValue s = o.field("scale");
      scale = s.json().is_number() ? glm::vec3(float(s.number())) : s.vec3();
      if (scale.x == 0 || scale.y == 0 || scale.z == 0) s.fail("zero scale: collapses the shape (zero area)");
    }
    return composeTransform(o.vec3("translate", glm::vec3(0)), o.vec3("rotate", glm::vec3(0)), scale);
  }

  void claimName(const JsonValue& where, const std::string& name) {
    if (name.empty()) where.fail("empty name");
    if (!m_names.insert(name).second)
      where.fail("duplicate name \"" + name + "\" (shape and light names must be unique)");
  }

  void parseShape(const JsonValue& value) {
    const std::string type = typeOf(value, {"rectangle", "cube", "sphere", "heightfield", "mesh"});
    std::vector<std::string_view> allowed = {"name", "type", "material", "transform", "emission"};
    if (type == "sphere") allowed.push_back("subdivisions");
    if (type == "heightfield") allowed.insert(allowed.end(), {"resolution", "size", "heights"});
    if (type == "mesh") allowed.push_back("file");
    const JsonObject o(value, allowed);

    const size_t index = m_scene.shapes.size();
    const std::string name = o.string("name", type + "_" + std::to_string(index));
    claimName(o.has("name") ? o.field("name") : value, name);
    const uint32_t material = materialFor(o);
    const float emission = float(o.number("emission", 0.0));
    if (o.has("emission")) requireAtLeast(o.field("emission"), emission, 0.0);
    const glm::mat4 transform = parseTransform(o);

    TriangleMesh mesh;
    if (type == "mesh") {
      const JsonValue fileField = o.field("file");
      const fs::path file = m_baseDir / fileField.string();
      const std::string ext = lowerExtension(file);
      if (ext != ".gltf" && ext != ".glb" && ext != ".obj" && ext != ".ply")
        fileField.fail("unknown mesh file extension \"" + ext + "\" (expected .obj, .ply, .gltf or .glb)");
      if (ext == ".gltf" || ext == ".glb") {
        try {
          appendGltfShapes(m_scene, file, material, transform, emission, name);
        } catch (const Error& e) {
          fileField.fail(e.what());
        }
        const Shape& shape = m_scene.shapes.back();
        if (!allFinite(shape.positions)) value.fail("transform takes vertex positions past the float range");
        const double area = meshArea(shape.positions, shape.triangles);
        if (area <= 0) value.fail("zero area: the mesh has no visible surface");
        requireFloatSurface(o, value, area, emission);
        return;
      }
      try {
        mesh = ext == ".obj" ? loadObjMesh(file) : loadPlyMesh(file);
      } catch (const Error& e) {
        fileField.fail(e.what());
      }
    }
    glm::uvec2 grid{0, 0};
    if (type == "rectangle") mesh = makeRectangle();
    if (type == "cube") mesh = makeCube();
    if (type == "sphere") mesh = makeIcosphere(o.uinteger("subdivisions", 3, 0, kMaxSphereSubdivisions));
    if (type == "heightfield") {
      mesh = parseHeightfield(o, grid);
      // One unit of a height in the file moves its vertex by the image of local +y.
      m_heightfieldUp[name] = glm::vec3(glm::mat3(transform) * glm::vec3(0, 1, 0));
    }
    transformMesh(mesh, transform);
    if (!allFinite(mesh.positions)) value.fail("transform takes vertex positions past the float range");
    const double area = meshArea(mesh.positions, mesh.triangles);
    if (!(area > 0)) value.fail("zero area: the shape has no visible surface");
    requireFloatSurface(o, value, area, emission);
    Shape shape;
    shape.name = name;
    shape.positions = std::move(mesh.positions);
    shape.triangles = std::move(mesh.triangles);
    shape.material = material;
    shape.emission = emission;
    shape.grid = grid;
    m_scene.shapes.push_back(std::move(shape));
  }

  // The device keeps each triangle's area, and the scene's emitted power, as floats (a quarter of
  // the range leaves room for the cross product that gives an area).
  static void requireFloatSurface(const JsonObject& o, const JsonValue& value, double area, float emission) {
    constexpr double kFloatMax = double(std::numeric_limits<float>::max());
    if (!(area <= kFloatMax / 4)) value.fail("surface area past the float range: the transform makes the shape too large");
    if (!(std::numbers::pi * double(emission) * area <= kFloatMax))
      o.field("emission").fail("emitted power (pi x emission x area) past the float range");
  }

  static TriangleMesh parseHeightfield(const JsonObject& o, glm::uvec2& grid) {
    const JsonValue res = o.field("resolution");
    if (!res.json().is_array() || res.json().size() != 2) res.fail("wrong type: expected [nx, nz] (2 integers)");
    const uint32_t nx = res.element(0).uinteger(2, kMaxHeightfieldResolution);
    const uint32_t nz = res.element(1).uinteger(2, kMaxHeightfieldResolution);
    const JsonValue size = o.field("size");
    const std::vector<double> s = size.numbers(2);
    requireAbove(size.element(0), s[0], 0.0);
    requireAbove(size.element(1), s[1], 0.0);
    const JsonValue heightsField = o.field("heights");
    const Json& array = heightsField.array();
    if (array.size() != size_t(nx) * nz)
      heightsField.fail("count mismatch: expected " + std::to_string(size_t(nx) * nz) + " heights (nx * nz = " +
                        std::to_string(nx) + " * " + std::to_string(nz) + "), got " + std::to_string(array.size()));
    std::vector<float> heights(array.size());
    for (size_t i = 0; i < array.size(); ++i) heights[i] = float(heightsField.element(i).number());
    grid = {nx, nz};
    return makeHeightfield(nx, nz, float(s[0]), float(s[1]), heights);
  }

  void parseLight(const JsonValue& value) {
    typeOf(value, {"point"});
    const JsonObject o(value, {"type", "name", "position", "intensity"});
    PointLight light;
    light.name = o.string("name", "light_" + std::to_string(m_scene.pointLights.size()));
    claimName(o.has("name") ? o.field("name") : value, light.name);
    light.position = o.field("position").vec3();
    light.intensity = float(o.number("intensity", 1.0));
    if (o.has("intensity")) requireAtLeast(o.field("intensity"), light.intensity, 0.0);
    m_scene.pointLights.push_back(light);
  }

  void parseRender(const JsonValue& value) {
    const JsonObject o(value, {"spp", "max_depth", "roulette_depth", "seed", "nee"});
    RenderSettings& r = m_scene.render;
    r.spp = o.uinteger("spp", r.spp, 1, 1u << 30);
    r.maxDepth = o.uinteger("max_depth", r.maxDepth, 1, 1024);
    r.rouletteDepth = o.uinteger("roulette_depth", r.rouletteDepth, 1, 1024);
    r.seed = o.uinteger("seed", r.seed, 0, std::numeric_limits<uint32_t>::max());
    if (o.has("nee")) r.nee = readNeeMode(o.field("nee"));
  }

  // Parameters (docs/scene-format.md "Parameters"): what each type binds to, read strictly, then
  // checked for a derivative that is not identically zero (parameterProblem).
  void parseParameter(const JsonValue& value) {
    const std::string type =
        typeOf(value, {"translate", "rotate", "displace", "heightfield_heights", "vertex_positions", "light_position",
                       "emission", "intensity", "albedo", "roughness", "ior", "gate_center"});
    if (type == "heightfield_heights" || type == "vertex_positions") {
      parseVertexExpansion(value, type == "heightfield_heights");
      return;
    }

    struct Form {
      const char* type;
      ParameterKind kind;
      const char* target;  // field naming the target, "" for none
    };
    static const Form kForms[] = {
        {"translate", ParameterKind::Translate, "shape"},   {"rotate", ParameterKind::Rotate, "shape"},
        {"displace", ParameterKind::Displace, "shape"},     {"light_position", ParameterKind::LightPosition, "light"},
        {"emission", ParameterKind::Emission, "shape"},     {"intensity", ParameterKind::Intensity, "light"},
        {"albedo", ParameterKind::Albedo, "material"},      {"roughness", ParameterKind::Roughness, "material"},
        {"ior", ParameterKind::Ior, "material"},            {"gate_center", ParameterKind::GateCenter, ""},
    };
    const Form& form = *std::find_if(std::begin(kForms), std::end(kForms), [&](const Form& f) { return type == f.type; });
    const std::string targetKey = form.target;
    std::vector<std::string_view> allowed = {"name", "type", "value"};
    if (!targetKey.empty()) allowed.push_back(targetKey);
    if (type == "translate" || type == "rotate" || type == "light_position") allowed.push_back("axis");
    if (type == "rotate") allowed.push_back("center");
    if (type == "displace") allowed.insert(allowed.end(), {"vertices", "direction"});
    const JsonObject o(value, allowed);

    Parameter p;
    p.kind = form.kind;
    p.name = o.field("name").string();
    claimParameterName(o.field("name"), p.name);
    if (!targetKey.empty()) {
      const JsonValue target = o.field(targetKey);
      p.target = target.string();
      const bool known = targetKey == "shape"   ? findShape(p.target) != nullptr
                         : targetKey == "light" ? std::any_of(m_scene.pointLights.begin(), m_scene.pointLights.end(),
                                                              [&](const PointLight& l) { return l.name == p.target; })
                                                : m_materials.count(p.target) > 0;
      if (!known) target.fail("unknown " + targetKey + " \"" + p.target + "\"");
    }
    if (type == "translate" || type == "rotate" || type == "light_position")
      p.axis = unitVector(o.field("axis"), "axis");
    if (type == "rotate") {
      const Shape& shape = *findShape(p.target);
      glm::vec3 lo = shape.positions.front(), hi = lo;
      for (const glm::vec3& v : shape.positions) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
      p.center = o.vec3("center", 0.5f * (lo + hi));
    }
    if (type == "displace") {
      p.axis = unitVector(o.field("direction"), "direction");
      p.vertices = readVertices(o.field("vertices"), *findShape(p.target));
    }
    const std::string problem = parameterProblem(m_scene, p);
    if (!problem.empty()) vktg::fail(m_file, o.pathOf(targetKey.empty() ? "type" : targetKey), problem);
    if (o.has("value")) m_values.push_back({uint32_t(m_scene.parameters.size()), o.field("value").number(), o.pathOf("value")});
    m_scene.parameters.push_back(std::move(p));
  }

  // Parameters given a `value` (the expanding types: `values`) start there: the scene is moved as
  // applyParameters would move it, in declaration order, and θ = 0 is that scene (how an optimised
  // scene is written back).
  void applyValues() {
    std::vector<std::pair<uint32_t, double>> values;
    for (const PendingValue& v : m_values) {
      const Parameter& p = m_scene.parameters[v.parameter];
      const ParameterRange range = parameterRange(m_scene, p);
      if (!range.contains(v.value))
        vktg::fail(m_file, v.path,
                   "value " + formatNumber(v.value) + " of parameter \"" + p.name +
                       "\" is outside the range its quantity allows (" + formatNumber(range.low) + " to " +
                       formatNumber(range.high) + " from the scene as written)");
      values.emplace_back(v.parameter, v.value);
    }
    if (!values.empty()) m_scene = applyParameters(m_scene, values);
  }

  // {"type": "heightfield_heights" or "vertex_positions", "shape": S, "name_prefix": P, "values": [...]}:
  // one displacement parameter per vertex and direction (vertexExpansion). Heights move along the
  // heightfield's transformed +y, so that θ_k is added to heights[k] of the file; positions along
  // the world axes, for any shape (free-form mesh recovery). `values`: every expanded parameter's
  // value, in the expansion's order.
  void parseVertexExpansion(const JsonValue& value, bool heights) {
    const JsonObject o(value, {"type", "shape", "name_prefix", "values"});
    const JsonValue shapeField = o.field("shape");
    const std::string shapeName = shapeField.string();
    const Shape* shape = findShape(shapeName);
    if (!shape) shapeField.fail("unknown shape \"" + shapeName + "\"");
    const VertexExpansion expansion = vertexExpansion(heights ? "heightfield_heights" : "vertex_positions", shapeName);
    std::vector<glm::vec3> directions = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
    if (heights) {
      const auto up = m_heightfieldUp.find(shapeName);
      if (up == m_heightfieldUp.end()) shapeField.fail("shape \"" + shapeName + "\" is not a heightfield");
      directions = {up->second};
    }
    const std::string prefix = o.string("name_prefix", expansion.defaultPrefix);
    const JsonValue where = o.has("name_prefix") ? o.field("name_prefix") : value;
    if (!isValidParameterName(prefix))
      where.fail("invalid name prefix \"" + prefix + "\" (use letters, digits, '_', '-' and '.')");
    const size_t count = shape->positions.size() * directions.size();
    std::vector<double> values;
    if (o.has("values")) values = o.field("values").numbers(count);
    for (size_t i = 0; i < count; ++i) {
      const uint32_t k = uint32_t(i / directions.size());
      Parameter p;
      p.name = prefix + std::to_string(k) + expansion.suffixes[i % directions.size()];
      p.kind = ParameterKind::Displace;
      p.target = shapeName;
      p.axis = directions[i % directions.size()];
      p.vertices = {k};
      claimParameterName(where, p.name);
      if (!values.empty() && values[i] != 0.0)
        m_values.push_back({uint32_t(m_scene.parameters.size()), values[i], o.pathOf("values") + "[" + std::to_string(i) + "]"});
      m_scene.parameters.push_back(std::move(p));
    }
  }

  struct PendingValue {
    uint32_t parameter;
    double value;
    std::string path;
  };
  std::vector<PendingValue> m_values;

  void claimParameterName(const JsonValue& where, const std::string& name) {
    if (!isValidParameterName(name))
      where.fail("invalid parameter name \"" + name + "\" (use letters, digits, '_', '-' and '.')");
    if (!m_parameterNames.insert(name).second) where.fail("duplicate parameter name \"" + name + "\"");
  }

  const Shape* findShape(const std::string& name) const {
    for (const Shape& shape : m_scene.shapes)
      if (shape.name == name) return &shape;
    return nullptr;
  }

  static glm::vec3 unitVector(const JsonValue& field, const char* what) {
    const glm::vec3 v = field.vec3();
    const float length = glm::length(v);
    if (!(length > 0)) field.fail(std::string("zero ") + what + ": it must give a direction");
    return v / length;
  }

  static std::vector<uint32_t> readVertices(const JsonValue& field, const Shape& shape) {
    const uint32_t count = uint32_t(shape.positions.size());
    std::vector<uint32_t> vertices;
    if (field.json().is_string()) {
      if (field.string() != "all") field.fail("unknown value \"" + field.string() + "\" (expected \"all\" or a list of vertex indices)");
      for (uint32_t i = 0; i < count; ++i) vertices.push_back(i);
      return vertices;
    }
    if (!field.json().is_array()) field.fail("wrong type: expected \"all\" or an array of vertex indices");
    if (field.json().empty()) field.fail("empty vertex list: nothing would move");
    std::set<uint32_t> seen;
    for (size_t i = 0; i < field.json().size(); ++i) {
      const JsonValue element = field.element(i);
      const uint32_t v = element.uinteger(0, std::numeric_limits<uint32_t>::max());
      if (v >= count)
        element.fail("vertex index " + std::to_string(v) + " out of range (shape \"" + shape.name + "\" has " +
                      std::to_string(count) + " vertices)");
      if (!seen.insert(v).second) element.fail("vertex index " + std::to_string(v) + " given twice");
      vertices.push_back(v);
    }
    return vertices;
  }

  std::string m_file;
  fs::path m_baseDir;
  Scene m_scene;
  std::map<std::string, uint32_t> m_materials;
  std::set<std::string> m_names;
  std::set<std::string> m_parameterNames;
  std::map<std::string, glm::vec3> m_heightfieldUp;  // heightfield shape -> world image of local +y
};

}  // namespace

Scene parseSceneJson(const std::string& text, const std::string& file, const std::filesystem::path& baseDir) {
  const Json json = parseJsonText(text, file);
  return SceneParser(file, baseDir).parse(json);
}

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

Scene withParameters(Scene scene, const JsonValue& parameters) {
  return SceneParser(parameters.file, {}).addParameters(std::move(scene), parameters);
}

Scene loadScene(const std::filesystem::path& path, const SceneDefines& defines) {
  const std::string ext = lowerExtension(path);
  if (ext == ".xml") return loadMitsubaScene(path, defines);
  if (!defines.empty())
    fail(path.string(), "-D " + defines.begin()->first, "defines apply to Mitsuba XML scenes only (this is a " + ext + " file)");
  if (ext == ".gltf" || ext == ".glb") return loadGltfScene(path);
  if (ext != ".json")
    fail(path.string(), "", "unknown scene file extension \"" + ext + "\" (expected .json, .xml, .gltf or .glb)");
  Scene scene = parseSceneJson(readTextFile(path), path.string(), path.parent_path());
  scene.source = path;
  return scene;
}

}  // namespace vktg
