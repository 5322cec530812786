// Mitsuba XML plugins onto vktg's scene: shapes, BSDFs, emitters, the integrator's depths, and the
// sensor (mitsuba_sensors.cpp) with its film and sampler. The file's tree comes from XmlDocument
// (includes, defaults, $name substitution); each plugin is read through a PluginElement, which fails
// on anything the mapping here does not take.
#include "scene/mitsuba_xml.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "scene/mesh_files.h"
#include "scene/mitsuba_plugin.h"
#include "scene/mitsuba_sensors.h"
#include "scene/mitsuba_values.h"
#include "scene/mitsuba_xml_document.h"
#include "scene/primitives.h"
#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// Tessellation of Mitsuba's analytic shapes. A disk is a 64-gon inscribed in the circle (area
// 0.16 % below pi); a sphere an icosphere of 5120 triangles inscribed in it (area 0.12 % below 4 pi).
constexpr uint32_t kDiskSegments = 64;
constexpr uint32_t kSphereSubdivisions = 4;
// vktg's smoothest microfacet surface stands for Mitsuba's smooth conductor and dielectric.
constexpr double kSmoothRoughness = 1e-3;
// Mitsuba's max_depth = -1 (no limit), and any depth past vktg's largest, become vktg's largest.
constexpr int64_t kMaxDepth = 1024;
constexpr double kFloatMax = double(std::numeric_limits<float>::max());

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

// The indices of refraction Mitsuba knows by name (measured near 589 nm, Hecht's Optics).
struct NamedIor {
  const char* name;
  double ior;
};
constexpr NamedIor kNamedIors[] = {
    {"vacuum", 1.0},           {"helium", 1.000036},      {"hydrogen", 1.000132},
    {"air", 1.000277},         {"carbon dioxide", 1.00045}, {"water", 1.3330},
    {"acetone", 1.36},         {"ethanol", 1.361},        {"carbon tetrachloride", 1.461},
    {"glycerol", 1.4729},      {"benzene", 1.501},        {"silicone oil", 1.52045},
    {"bromine", 1.661},        {"water ice", 1.31},       {"fused quartz", 1.458},
    {"pyrex", 1.470},          {"acrylic glass", 1.49},   {"polypropylene", 1.49},
    {"bk7", 1.5046},           {"sodium chloride", 1.544}, {"amber", 1.55},
    {"pet", 1.5750},           {"diamond", 2.419},
};

// int_ior / ext_ior: a number or one of the names above.
double readIor(PluginElement& e, std::string_view name, const char* fallback) {
  std::string text = fallback;
  if (e.has(name)) {
    const XmlNode& node = e.propertyNode(name);
    if (node.tag != "string") {
      const double v = *e.number(name);
      if (!(v > 0)) e.document().fail(node, std::string(name) + " must be positive");
      return v;
    }
    text = *e.string(name);
  }
  for (const NamedIor& entry : kNamedIors)
    if (lower(text) == entry.name) return entry.ior;
  std::string known;
  for (const NamedIor& entry : kNamedIors) known += (known.empty() ? "" : ", ") + std::string(entry.name);
  e.document().fail(e.propertyNode(name), "unknown material " + quote(text) + " (Mitsuba's names: " + known + ")");
}

// A reflectance: every channel in [0, 1], the mean of them.
double readReflectance(PluginElement& e, std::string_view name, double fallback) {
  const std::optional<XmlColor> color = e.color(name);
  if (!color) return fallback;
  for (double c : color->channels)
    if (!(c >= 0 && c <= 1))
      e.document().fail(*color->node, std::string(name) + " must lie in [0, 1] in every channel (vktg's albedo is a fraction)");
  return color->mean();
}

// Emitted radiance or intensity: every channel >= 0, the mean of them.
double readEmission(PluginElement& e, std::string_view name) {
  const std::optional<XmlColor> color = e.color(name);
  if (!color) return 1.0;  // Mitsuba's default for area and point emitters
  for (double c : color->channels)
    if (!(c >= 0)) e.document().fail(*color->node, std::string(name) + " must not be negative");
  const double mean = color->mean();
  if (!(mean <= kFloatMax)) e.document().fail(*color->node, std::string(name) + " is past the float range");
  return mean;
}

// distribution and alpha of Mitsuba's rough conductor and dielectric, as vktg's GGX roughness.
double readMicrofacetRoughness(PluginElement& e) {
  const std::optional<std::string> distribution = e.string("distribution");
  if (!distribution)
    e.fail("Mitsuba's default microfacet distribution is beckmann, and vktg renders GGX: give "
           "<string name=\"distribution\" value=\"ggx\"/>");
  if (lower(*distribution) != "ggx")
    e.document().fail(e.propertyNode("distribution"), "vktg renders the ggx distribution only");
  e.boolean("sample_visible");  // how directions are sampled, not the BSDF
  double alpha = 0.1;
  if (e.has("alpha_u") || e.has("alpha_v")) {
    if (!e.has("alpha_u") || !e.has("alpha_v")) e.fail("give both alpha_u and alpha_v, or alpha");
    if (e.has("alpha")) e.fail("give alpha or alpha_u and alpha_v, not both");
    const double u = *e.number("alpha_u"), v = *e.number("alpha_v");
    if (u != v) e.document().fail(e.propertyNode("alpha_v"), "anisotropic roughness (alpha_u != alpha_v) is not supported");
    alpha = u;
  } else if (e.has("alpha")) {
    alpha = *e.number("alpha");
  }
  if (!(alpha > 0 && alpha <= 1)) e.fail("alpha must lie in (0, 1] (vktg's GGX roughness)");
  return std::max(alpha, kSmoothRoughness);
}

// Normal-incidence reflectance of a conductor of complex index eta + i k (per channel), times
// specular_reflectance, averaged over the channels: vktg's conductor albedo (its Schlick F0).
double conductorReflectance(PluginElement& e) {
  const std::string material = e.string("material").value_or("none");
  if (material != "none")
    e.document().fail(e.propertyNode("material"),
                      "named conductors need Mitsuba's spectral data: give eta and k (or material=\"none\" for a mirror)");
  const std::optional<XmlColor> eta = e.color("eta"), k = e.color("k");
  const std::optional<XmlColor> tint = e.color("specular_reflectance");
  const std::vector<double> etas = eta ? eta->channels : std::vector<double>{0.0};
  const std::vector<double> ks = k ? k->channels : std::vector<double>{1.0};
  const std::vector<double> tints = tint ? tint->channels : std::vector<double>{1.0};
  const size_t count = std::max({etas.size(), ks.size(), tints.size()});
  for (const std::vector<double>* list : {&etas, &ks, &tints})
    if (list->size() != 1 && list->size() != count)
      e.fail("eta, k and specular_reflectance must hold the same number of values (or one, for all channels)");
  for (double v : etas)
    if (!(v >= 0)) e.document().fail(*eta->node, "eta must not be negative");
  for (double v : ks)
    if (!(v >= 0)) e.document().fail(*k->node, "k must not be negative");
  for (double v : tints)
    if (!(v >= 0 && v <= 1)) e.document().fail(*tint->node, "specular_reflectance must lie in [0, 1] in every channel");
  double sum = 0;
  for (size_t c = 0; c < count; ++c) {
    const double n = etas[etas.size() == 1 ? 0 : c], kappa = ks[ks.size() == 1 ? 0 : c];
    const double f0 = ((n - 1) * (n - 1) + kappa * kappa) / ((n + 1) * (n + 1) + kappa * kappa);
    sum += tints[tints.size() == 1 ? 0 : c] * f0;
  }
  return sum / double(count);
}

struct BsdfRead {
  Material material;
  bool twoSided = false;  // reflects on both sides in Mitsuba too
};

BsdfRead readBsdf(const XmlDocument& document, const XmlNode& node, bool nested) {
  PluginElement e(document, node);
  BsdfRead read;
  Material& m = read.material;
  const std::string& type = e.type();
  if (type == "diffuse") {
    m.type = MaterialType::Diffuse;
    m.albedo = float(readReflectance(e, "reflectance", 0.5));
  } else if (type == "conductor" || type == "roughconductor") {
    m.type = MaterialType::Conductor;
    m.albedo = float(conductorReflectance(e));
    m.roughness = float(type == "conductor" ? kSmoothRoughness : readMicrofacetRoughness(e));
  } else if (type == "dielectric" || type == "roughdielectric") {
    m.type = MaterialType::Dielectric;
    m.albedo = 1.0f;
    const double inside = readIor(e, "int_ior", "bk7"), outside = readIor(e, "ext_ior", "air");
    const double ior = inside / outside;
    if (!(ior > 1.0))
      e.fail("vktg's dielectric needs int_ior / ext_ior > 1 (got " + formatNumber(ior) + "): turn the shape inside out instead");
    m.ior = float(ior);
    for (const char* key : {"specular_reflectance", "specular_transmittance"})
      if (const std::optional<XmlColor> c = e.color(key))
        for (double v : c->channels)
          if (v != 1.0) document.fail(*c->node, std::string(key) + " must be 1: vktg's dielectric loses no energy");
    m.roughness = float(type == "dielectric" ? kSmoothRoughness : readMicrofacetRoughness(e));
    read.twoSided = true;
  } else if (type == "twosided") {
    if (nested) e.fail("a twosided BSDF inside another is not supported");
    const std::vector<const XmlNode*> inner = e.objects("bsdf");
    if (inner.empty()) e.fail("a twosided BSDF needs the BSDF it wraps");
    if (inner.size() > 1) document.fail(*inner[1], "a different BSDF per side is not supported (vktg gives a shape one material)");
    const BsdfRead wrapped = readBsdf(document, *inner.front(), true);
    if (wrapped.material.type == MaterialType::Dielectric)
      document.fail(*inner.front(), "twosided wraps BSDFs without transmission (Mitsuba refuses a dielectric here too)");
    m = wrapped.material;
    read.twoSided = true;
  } else {
    e.fail("unsupported BSDF (vktg reads diffuse, conductor, roughconductor, dielectric, roughdielectric, twosided)");
  }
  e.finish();
  return read;
}

struct IntegratorSettings {
  std::string type = "path";        // Mitsuba's path tracer when the file names none
  int64_t maxDepth = -1, rrDepth = 5;
  std::optional<bool> accounts;     // transient_nlos_path's account_first_and_last_bounces
  const XmlNode* node = nullptr;
  bool transient() const { return type != "path"; }
};

IntegratorSettings readIntegrator(const XmlDocument& document, const XmlNode& node) {
  PluginElement e(document, node);
  IntegratorSettings s;
  s.node = &node;
  s.type = e.type();
  if (s.type != "path" && s.type != "transient_path" && s.type != "transient_nlos_path")
    e.fail("unsupported integrator (vktg reads path, transient_path and transient_nlos_path)");
  // Mitsuba's C++ path tracer has no depth limit by default; its Python (mitransient) ones stop at 6.
  s.maxDepth = e.integer("max_depth").value_or(s.transient() ? 6 : -1);
  if (s.maxDepth < -1) document.fail(e.propertyNode("max_depth"), "max_depth must be -1 (no limit) or >= 0");
  if (s.maxDepth == 0) document.fail(e.propertyNode("max_depth"), "max_depth = 0 renders nothing");
  s.rrDepth = e.integer("rr_depth").value_or(5);
  if (s.rrDepth < 1) document.fail(e.propertyNode("rr_depth"), "rr_depth must be at least 1");
  if (e.boolean("hide_emitters").value_or(false))
    document.fail(e.propertyNode("hide_emitters"), "hide_emitters is not supported (vktg shows emitters the camera sees)");
  if (s.transient()) {
    if (e.boolean("camera_unwarp").value_or(false))
      document.fail(e.propertyNode("camera_unwarp"), "camera_unwarp is not supported: vktg's times count the camera's leg");
    if (e.boolean("discard_direct_light").value_or(false))
      document.fail(e.propertyNode("discard_direct_light"), "discard_direct_light is not supported");
    const std::string filter = lower(e.string("temporal_filter").value_or(""));
    if (filter != "" && filter != "box")
      document.fail(e.propertyNode("temporal_filter"), "vktg's time bins are boxes: temporal_filter must be box");
    e.number("gaussian_stddev");  // for a gaussian temporal filter only
    e.integer("block_size");      // how Mitsuba splits the work
  }
  if (s.type == "transient_nlos_path") {
    for (const char* key : {"filter_depth", "filter_bounces"})
      if (e.integer(key).value_or(-1) != -1) document.fail(e.propertyNode(key), std::string(key) + " is not supported");
    if (e.boolean("discard_direct_paths").value_or(false))
      document.fail(e.propertyNode("discard_direct_paths"), "discard_direct_paths is not supported");
    // Sampling strategies for NLOS paths: they change the noise, not the expected value.
    for (const char* key : {"nlos_laser_sampling", "nlos_hidden_geometry_sampling", "nlos_hidden_geometry_sampling_do_rroulette",
                            "nlos_hidden_geometry_sampling_includes_relay_wall", "force_equal_illumination_scanning"})
      e.boolean(key);
    e.number("illumination_scan_fov");  // exhaustive captures only
    if (e.has("capture_type")) {
      const XmlNode& p = e.propertyNode("capture_type");
      const bool single = p.tag == "string" ? lower(*e.string("capture_type")) == "single" : e.integer("capture_type") == 1;
      if (!single)
        document.fail(p, "only single captures are read from capture_type; for a confocal scan set confocal=true on the "
                         "nlos_capture_meter");
    }
    s.accounts = e.boolean("account_first_and_last_bounces");
  }
  e.finish();
  return s;
}

// vktg counts a path's segments, connections included, as Mitsuba does; an NLOS capture's scan
// leaves out the legs from the device to the wall and back, two of Mitsuba's segments.
uint32_t vktgDepth(int64_t mitsubaDepth, int64_t legsOutside) {
  if (mitsubaDepth == -1) return uint32_t(kMaxDepth);
  return uint32_t(std::clamp<int64_t>(mitsubaDepth - legsOutside, 1, kMaxDepth));
}

struct Wall {
  const XmlNode* meter = nullptr;  // the nlos_capture_meter on this shape
  RelayWall wall;
  const XmlNode* shape = nullptr;
};

class SceneBuilder {
 public:
  explicit SceneBuilder(const XmlDocument& document) : m_document(document) {
    for (const std::string& id : document.ids()) m_taken.insert(id);
  }

  MitsubaScene build() {
    const XmlDocument& doc = m_document;
    for (const XmlNode& child : doc.root().children)
      if (child.tag == "ref")
        doc.fail(child, "a <ref> at the top of the scene would add its target a second time (refer to BSDFs inside shapes)");
    PluginElement root(doc, doc.root());
    const std::vector<const XmlNode*> textures = root.objects("texture");
    if (!textures.empty()) doc.fail(*textures.front(), "textures are not supported");
    // Every top-level BSDF is read, so that a mistake in one no shape uses still shows.
    for (const XmlNode* bsdf : root.objects("bsdf")) readBsdf(doc, *bsdf, false);
    const std::vector<const XmlNode*> integrators = root.objects("integrator");
    if (integrators.size() > 1) doc.fail(*integrators[1], "a scene takes one integrator");
    IntegratorSettings integrator;
    if (!integrators.empty()) integrator = readIntegrator(doc, *integrators.front());
    const std::vector<const XmlNode*> sensors = root.objects("sensor");
    const std::vector<const XmlNode*> shapes = root.objects("shape");
    const std::vector<const XmlNode*> emitters = root.objects("emitter");
    root.finish();

    for (const XmlNode* shape : shapes) readShape(*shape);
    const XmlNode* projector = nullptr;
    for (const XmlNode* emitter : emitters) readSceneEmitter(*emitter, projector);

    MitsubaScene out;
    const size_t sensorCount = sensors.size() + m_walls.size();
    if (sensorCount == 0) doc.fail(doc.root(), "no sensor: the scene needs a perspective sensor or an nlos_capture_meter");
    if (sensorCount > 1) {
      const XmlNode& second = sensors.size() > 1 ? *sensors[1] : m_walls.size() > 1 ? *m_walls[1].meter
                                                                                     : *m_walls.front().meter;
      doc.fail(second, "vktg renders one sensor; this scene has " + std::to_string(sensorCount));
    }
    FilmSettings film;
    SamplerSettings sampler;
    int64_t legsOutside = 0;
    const XmlNode* sensorNode = nullptr;
    if (!m_walls.empty()) {
      const Wall& wall = m_walls.front();
      sensorNode = wall.meter;
      if (!integrator.transient())
        doc.fail(integrator.node ? *integrator.node : *wall.meter,
                 "an nlos_capture_meter needs a transient integrator (transient_nlos_path or transient_path)");
      PluginElement meter(doc, *wall.meter);
      NlosCapture capture = readNlosCaptureMeter(meter, wall.wall, projector, integrator.accounts,
                                                 uint32_t(m_scene.pointLights.size()));
      capture.laser.name = claimName(capture.laser.name, capture.laserNamedById);
      m_scene.pointLights.push_back(capture.laser);
      m_scene.camera = capture.camera;
      film = capture.film;
      sampler = capture.sampler;
      out.capture = std::move(capture.scan);
      legsOutside = 2;
    } else {
      if (projector) doc.fail(*projector, "a projector is read only as the laser of an nlos_capture_meter");
      sensorNode = sensors.front();
      PluginElement sensor(doc, *sensorNode);
      if (sensor.type() == "nlos_capture_meter")
        sensor.fail("an nlos_capture_meter belongs inside the relay wall's <shape>");
      if (sensor.type() != "perspective") sensor.fail("unsupported sensor (vktg reads perspective, and nlos_capture_meter in a shape)");
      const std::vector<const XmlNode*> films = sensor.objects("film");
      if (films.size() > 1) doc.fail(*films[1], "a sensor takes one film");
      const std::vector<const XmlNode*> samplers = sensor.objects("sampler");
      if (samplers.size() > 1) doc.fail(*samplers[1], "a sensor takes one sampler");
      film = readFilm(doc, films.empty() ? nullptr : films.front());
      sampler = readSampler(doc, samplers.empty() ? nullptr : samplers.front());
      m_scene.camera = readPerspectiveCamera(sensor, film);
      sensor.finish();
      // transient_nlos_path leaves the camera's first segment and the last connection out of a
      // path's time unless told otherwise, which no gate of a pinhole view can express.
      if (integrator.type == "transient_nlos_path" && integrator.accounts != true)
        doc.fail(*integrator.node, "behind a perspective sensor transient_nlos_path needs account_first_and_last_bounces = "
                                   "true (else its times leave out the camera's and the light's segments)");
    }
    if (film.transient != integrator.transient()) {
      const XmlNode& where = film.node ? *film.node : *sensorNode;
      doc.fail(where, film.transient ? "a transient_hdr_film needs a transient integrator (transient_path or transient_nlos_path)"
                                     : "a transient integrator needs a transient_hdr_film");
    }
    if (integrator.node && integrator.maxDepth != -1 && integrator.maxDepth <= legsOutside)
      doc.fail(*integrator.node, "max_depth = " + std::to_string(integrator.maxDepth) +
                                     " ends every path before it leaves the relay wall (it counts the legs to the wall and back)");
    m_scene.gate = film.gate;
    m_scene.render.spp = sampler.spp;
    m_scene.render.seed = sampler.seed;
    m_scene.render.maxDepth = vktgDepth(integrator.maxDepth, legsOutside);
    m_scene.render.rouletteDepth = vktgDepth(integrator.rrDepth, legsOutside);

    if (!m_scene.hasEmitters())
      doc.fail(doc.root(), "no emitter: the scene needs an area emitter in a shape, a point emitter or a laser, emitting more than 0");
    if (!(m_scene.emittedPower() <= kFloatMax)) doc.fail(doc.root(), "the emitters' power summed is past the float range");
    m_scene.source = doc.mainFile();
    out.scene = std::move(m_scene);
    return out;
  }

 private:
  // `name` as given by an id, else a generated one that no id and no earlier name takes.
  std::string claimName(const std::string& base, bool fromId) {
    if (fromId) return base;
    std::string name = base;
    for (uint32_t k = 2; !m_taken.insert(name).second; ++k) name = base + "_" + std::to_string(k);
    return name;
  }

  uint32_t materialFor(const XmlNode* bsdf, const std::string& shapeName, bool& twoSided) {
    if (!bsdf) {
      // Mitsuba gives a shape without a BSDF a diffuse one of reflectance 0.5.
      if (!m_defaultMaterial) {
        Material m{claimMaterialName("default", false), MaterialType::Diffuse, 0.5f};
        m_defaultMaterial = uint32_t(m_scene.materials.size());
        m_scene.materials.push_back(m);
      }
      twoSided = false;
      return *m_defaultMaterial;
    }
    const auto known = m_materials.find(bsdf);
    if (known != m_materials.end()) {
      twoSided = known->second.second;
      return known->second.first;
    }
    BsdfRead read = readBsdf(m_document, *bsdf, false);
    const std::string* id = bsdf->attribute("id");
    read.material.name = claimMaterialName(id ? *id : shapeName + "_bsdf", id != nullptr);
    const uint32_t index = uint32_t(m_scene.materials.size());
    m_scene.materials.push_back(read.material);
    m_materials.emplace(bsdf, std::pair(index, read.twoSided));
    twoSided = read.twoSided;
    return index;
  }

  std::string claimMaterialName(const std::string& base, bool fromId) {
    if (fromId) return base;
    std::string name = base;
    for (uint32_t k = 2; !m_takenMaterials.insert(name).second || m_taken.count(name); ++k) name = base + "_" + std::to_string(k);
    return name;
  }

  void readShape(const XmlNode& node) {
    const XmlDocument& doc = m_document;
    PluginElement e(doc, node);
    const std::string& type = e.type();
    Shape shape;
    shape.name = claimName(e.id().empty() ? type + "_" + std::to_string(m_scene.shapes.size()) : e.id(), !e.id().empty());
    glm::dmat4 toWorld = e.transform("to_world").value_or(glm::dmat4(1.0));
    const bool flip = e.boolean("flip_normals").value_or(false);
    e.number("silhouette_sampling_weight");  // where Mitsuba's edge sampling looks
    TriangleMesh mesh;
    if (type == "rectangle") {
      mesh = makeRectangle();
    } else if (type == "cube") {
      mesh = makeCube();
    } else if (type == "disk") {
      mesh = makeDisk(kDiskSegments);
    } else if (type == "sphere") {
      const glm::dvec3 centre = e.point("center").value_or(glm::dvec3(0.0));
      const double radius = e.number("radius").value_or(1.0);
      if (!(radius > 0)) doc.fail(e.propertyNode("radius"), "radius must be positive");
      toWorld = toWorld * glm::dmat4(glm::dvec4(radius, 0, 0, 0), glm::dvec4(0, radius, 0, 0), glm::dvec4(0, 0, radius, 0),
                                     glm::dvec4(centre, 1.0));
      // Mitsuba's sphere stays round whatever to_world says (it keeps only a centre and radius).
      const glm::dmat3 linear(toWorld);
      const double scale2 = glm::dot(linear[0], linear[0]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (std::abs(glm::dot(linear[i], linear[j]) - (i == j ? scale2 : 0.0)) > 1e-3 * scale2)
            e.fail("a sphere's to_world must not shear or scale unevenly (Mitsuba keeps it a sphere; use an obj for an ellipsoid)");
      if (glm::determinant(linear) < 0) e.fail("a mirroring to_world on a sphere is not supported: use flip_normals");
      if (!m_unitSphere) m_unitSphere = makeIcosphere(kSphereSubdivisions);  // once: a scene may hold many
      mesh = *m_unitSphere;
    } else if (type == "obj" || type == "ply") {
      const std::optional<std::string> filename = e.string("filename");
      if (!filename) e.fail("missing property \"filename\"");
      e.boolean("face_normals");     // vktg shades with face normals always
      e.boolean("flip_tex_coords");  // no textures
      const fs::path named = *filename;
      const fs::path path = named.is_absolute() ? named : doc.mainFile().parent_path() / named;
      try {
        mesh = type == "obj" ? loadObjMesh(path) : loadPlyMesh(path);
      } catch (const Error& error) {
        doc.fail(e.propertyNode("filename"), error.what());
      }
    } else {
      e.fail("unsupported shape (vktg reads rectangle, cube, sphere, disk, obj, ply)");
    }
    transformMesh(mesh, glm::mat4(toWorld));
    if (flip)
      for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    if (!allFinite(mesh.positions)) e.fail("to_world takes vertex positions past the float range");
    const double area = meshArea(mesh.positions, mesh.triangles);
    if (!(area > 0)) e.fail("zero area: the shape has no visible surface");
    if (!(area <= kFloatMax / 4)) e.fail("surface area past the float range: to_world makes the shape too large");

    const std::vector<const XmlNode*> bsdfs = e.objects("bsdf");
    if (bsdfs.size() > 1) doc.fail(*bsdfs[1], "a shape takes one BSDF");
    bool twoSided = false;
    shape.material = materialFor(bsdfs.empty() ? nullptr : bsdfs.front(), shape.name, twoSided);

    const std::vector<const XmlNode*> emitters = e.objects("emitter");
    if (emitters.size() > 1) doc.fail(*emitters[1], "a shape takes one emitter");
    if (!emitters.empty()) shape.emission = float(readAreaEmitter(*emitters.front()));
    if (!(std::numbers::pi * double(shape.emission) * area <= kFloatMax))
      doc.fail(*emitters.front(), "emitted power (pi x radiance x area) past the float range");

    const std::vector<const XmlNode*> sensors = e.objects("sensor");
    if (sensors.size() > 1) doc.fail(*sensors[1], "a shape takes one sensor");
    if (!sensors.empty()) {
      const std::string* sensorType = sensors.front()->attribute("type");
      if (!sensorType || *sensorType != "nlos_capture_meter")
        doc.fail(*sensors.front(), "the sensor a shape holds must be mitransient's nlos_capture_meter");
      if (type != "rectangle")
        e.fail("an nlos_capture_meter's relay wall must be a rectangle (its grid follows the rectangle's uv; "
               "mitransient samples other shapes by area)");
      const Material& material = m_scene.materials[shape.material];
      if (material.type != MaterialType::Diffuse)
        e.fail("the relay wall of an nlos_capture_meter must be diffuse (its laser spot and sensor points are Lambertian)");
      Wall wall;
      wall.meter = sensors.front();
      wall.shape = &node;
      wall.wall.toWorld = toWorld;
      wall.wall.flipNormals = flip;
      wall.wall.albedo = material.albedo;
      wall.wall.twoSided = twoSided;
      m_walls.push_back(wall);
    }
    e.finish();
    shape.positions = std::move(mesh.positions);
    shape.triangles = std::move(mesh.triangles);
    m_scene.shapes.push_back(std::move(shape));
  }

  // The radiance of an area emitter in a shape (mitransient's angulararea where it emits over the
  // whole front hemisphere, which makes it an area emitter).
  double readAreaEmitter(const XmlNode& node) {
    PluginElement e(m_document, node);
    if (e.type() == "angulararea") {
      const double cutoff = e.number("cutoff_angle").value_or(10.0);
      const double beam = e.number("beam_width").value_or(cutoff);
      if (!(cutoff >= 90 && beam >= 90))
        e.fail("an angulararea emitter narrower than the hemisphere (cutoff_angle and beam_width below 90 degrees) is "
               "not supported; at 90 or more it is an area emitter");
    } else if (e.type() != "area") {
      e.fail("the emitter inside a shape must be an area emitter");
    }
    if (e.has("to_world")) m_document.fail(e.propertyNode("to_world"), "an area emitter takes its shape's to_world");
    const double radiance = readEmission(e, "radiance");
    e.number("sampling_weight");  // how often Mitsuba samples it
    e.finish();
    return radiance;
  }

  void readSceneEmitter(const XmlNode& node, const XmlNode*& projector) {
    PluginElement e(m_document, node);
    if (e.type() == "projector") {
      if (projector) e.fail("a second projector: an NLOS capture has one laser");
      projector = &node;  // read by the capture, which knows the wall
      return;
    }
    if (e.type() == "area" || e.type() == "angulararea") e.fail("an area emitter belongs inside a <shape>");
    if (e.type() != "point")
      e.fail("unsupported emitter (vktg reads point, area and angulararea in a shape, and a projector as an NLOS laser)");
    PointLight light;
    light.name = claimName(e.id().empty() ? "point_" + std::to_string(m_scene.pointLights.size()) : e.id(), !e.id().empty());
    const std::optional<glm::dvec3> position = e.point("position");
    const std::optional<glm::dmat4> toWorld = e.transform("to_world");
    if (position && toWorld) e.fail("give position or to_world, not both");
    const glm::dvec3 p = position ? *position : toWorld ? glm::dvec3((*toWorld)[3]) : glm::dvec3(0.0);
    light.position = glm::vec3(p);
    if (!allFinite({light.position})) e.fail("the position is past the float range");
    light.intensity = float(readEmission(e, "intensity"));
    e.number("sampling_weight");
    e.finish();
    m_scene.pointLights.push_back(light);
  }

  const XmlDocument& m_document;
  Scene m_scene;
  std::set<std::string> m_taken;           // shape and light names, and every id
  std::set<std::string> m_takenMaterials;  // generated material names
  std::map<const XmlNode*, std::pair<uint32_t, bool>> m_materials;  // BSDF -> material, whether two-sided
  std::optional<uint32_t> m_defaultMaterial;
  std::vector<Wall> m_walls;
  std::optional<TriangleMesh> m_unitSphere;
};

}  // namespace

bool isMitsubaXmlPath(const fs::path& path) { return lower(path.extension().string()) == ".xml"; }

MitsubaScene loadMitsubaXml(const fs::path& path, const SceneDefines& defines) {
  const XmlDocument document(path, defines);
  return SceneBuilder(document).build();
}

Scene loadMitsubaScene(const fs::path& path, const SceneDefines& defines) { return loadMitsubaXml(path, defines).scene; }

}  // namespace vktg
