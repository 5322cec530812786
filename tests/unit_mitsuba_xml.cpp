// Mitsuba 3 / mitransient XML scenes (docs/scene-format.md, "Mitsuba 3 XML"): every mapping onto
// vktg's scene against hand-computed values, the NLOS capture meter's scan, and every refusal naming
// file, line and element.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scene/mitsuba_values.h"
#include "scene/mitsuba_xml.h"
#include "scene/mitsuba_xml_document.h"
#include "scene/primitives.h"
#include "support/file_test.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::expectError;
using test::writePlain;

const fs::path kScenes = fs::path(VKTG_SOURCE_DIR) / "scenes";
const fs::path kData = fs::path(VKTG_TEST_DATA) / "mitsuba";
constexpr double kPi = std::numbers::pi;

// A perspective camera, a film and an integrator around `body`; tests splice shapes and emitters in.
std::string sceneWith(const std::string& body, const std::string& sensorExtra = "",
                      const std::string& integrator = "<integrator type=\"path\"/>") {
  return "<scene version=\"3.0.0\">\n" + integrator +
         "\n<sensor type=\"perspective\">\n"
         "  <transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n"
         "  <film type=\"hdrfilm\"><integer name=\"width\" value=\"32\"/><integer name=\"height\" value=\"16\"/></film>\n" +
         sensorExtra + "</sensor>\n" + body + "\n</scene>\n";
}

const std::string kLight = "<emitter type=\"point\"><point name=\"position\" value=\"0, 0, 4\"/></emitter>";

// The 1-based line of the first occurrence of `needle` in `text`.
size_t lineOf(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n')) + 1;
}

class MitsubaXml : public test::TempDirTest {
 protected:
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = m_dir / name;
    fs::create_directories(path.parent_path());
    writePlain(path, text);
    return path;
  }
  MitsubaScene load(const std::string& text, const SceneDefines& defines = {}) {
    return loadMitsubaXml(write("scene.xml", text), defines);
  }
  // The error must name the file, the line of `marker` and `element`, and hold every part.
  void expectRefused(const std::string& text, const std::string& marker, const std::string& element,
                     const std::vector<std::string>& parts, const SceneDefines& defines = {}) {
    const fs::path path = write("scene.xml", text);
    std::vector<std::string> all = {path.string() + ":" + std::to_string(lineOf(text, marker)) + ": " + element};
    all.insert(all.end(), parts.begin(), parts.end());
    expectError([&] { loadMitsubaXml(path, defines); }, all);
  }
};

void expectNear(glm::vec3 a, glm::vec3 b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

glm::vec3 frontNormal(const Shape& s, size_t i) {
  const glm::uvec3 t = s.triangles[i];
  return glm::normalize(glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]));
}

// ---- the default room ----

// scenes/default_room.xml is the built-in default scene: the same triangles (to float rounding:
// the XML's transforms are composed in double), materials, emission, camera, gate and settings.
TEST_F(MitsubaXml, DefaultRoomLoadsAsTheBuiltInDefaultScene) {
  const Scene xml = loadScene(kScenes / "default_room.xml");
  const Scene builtIn = defaultScene();
  ASSERT_EQ(xml.shapes.size(), builtIn.shapes.size());
  for (size_t s = 0; s < xml.shapes.size(); ++s) {
    const Shape &a = xml.shapes[s], &b = builtIn.shapes[s];
    SCOPED_TRACE(b.name);
    ASSERT_EQ(a.positions.size(), b.positions.size());
    EXPECT_EQ(a.triangles, b.triangles);
    for (size_t v = 0; v < a.positions.size(); ++v) expectNear(a.positions[v], b.positions[v], 1e-6f);
    const Material &ma = xml.materials[a.material], &mb = builtIn.materials[b.material];
    EXPECT_EQ(ma.name, mb.name);
    EXPECT_EQ(ma.type, mb.type);
    EXPECT_EQ(ma.albedo, mb.albedo);
    EXPECT_EQ(a.emission, b.emission);
  }
  EXPECT_EQ(xml.shapes[3].name, "left_wall");  // Mitsuba's ids are one namespace: the wall and its BSDF differ
  EXPECT_EQ(xml.camera.type, builtIn.camera.type);
  EXPECT_EQ(xml.camera.position, builtIn.camera.position);
  expectNear(glm::normalize(xml.camera.lookAt - xml.camera.position),
             glm::normalize(builtIn.camera.lookAt - builtIn.camera.position), 1e-7f);
  EXPECT_EQ(xml.camera.up, builtIn.camera.up);
  EXPECT_NEAR(xml.camera.fovY, builtIn.camera.fovY, 1e-5f);
  EXPECT_EQ(xml.camera.width, builtIn.camera.width);
  EXPECT_EQ(xml.camera.height, builtIn.camera.height);
  EXPECT_EQ(xml.gate, builtIn.gate);
  EXPECT_EQ(xml.render, builtIn.render);
  EXPECT_TRUE(xml.pointLights.empty());
  EXPECT_EQ(xml.source, kScenes / "default_room.xml");
}

// ---- transforms ----

// Each element is applied after the ones before it: translate, then rotate, then scale here.
TEST_F(MitsubaXml, TransformElementsComposeInFileOrder) {
  const MitsubaScene m = load(sceneWith(
      "<shape type=\"rectangle\"><transform name=\"to_world\">"
      "<translate x=\"1\"/><rotate y=\"1\" angle=\"90\"/><scale value=\"2\"/>"
      "</transform></shape>" + kLight));
  const Shape& s = m.scene.shapes.at(0);
  // Vertex (x, y, 0) -> (x + 1, y, 0) -> rotated 90 degrees about +y: (0, y, -(x + 1)) -> doubled.
  expectNear(s.positions[0], {0, -2, 0});   // (-1, -1, 0)
  expectNear(s.positions[1], {0, -2, -4});  // (1, -1, 0)
  expectNear(s.positions[2], {0, 2, -4});   // (1, 1, 0)
  // The front face (+z) turned with it: towards +x.
  for (size_t t = 0; t < s.triangles.size(); ++t) expectNear(frontNormal(s, t), {1, 0, 0});
}

TEST_F(MitsubaXml, MatrixIsRowMajorAndRotationIsCounterClockwise) {
  const MitsubaScene m = load(sceneWith(
      "<shape type=\"rectangle\"><transform name=\"to_world\">"
      "<matrix value=\"0 0 1 5  0 1 0 6  -1 0 0 7  0 0 0 1\"/></transform></shape>"
      "<shape type=\"rectangle\"><transform name=\"to_world\"><rotate value=\"0 0 1\" angle=\"90\"/>"
      "<scale x=\"3\"/></transform></shape>" + kLight));
  // Row-major: x' = z + 5, y' = y + 6, z' = -x + 7, so (1, -1, 0) -> (5, 5, 6).
  expectNear(m.scene.shapes[0].positions[1], {5, 5, 6});
  // 90 degrees about +z takes +x to +y; the scale after it stretches world x: (1, -1, 0) -> (1, 1, 0) -> (3, 1, 0).
  expectNear(m.scene.shapes[1].positions[1], {3, 1, 0});
}

TEST_F(MitsubaXml, LookAtAndTransformParsing) {
  const fs::path path = write("t.xml",
                              "<scene version=\"3.0.0\"><shape type=\"cube\"><transform name=\"to_world\">"
                              "<lookat origin=\"1 2 3\" target=\"1 2 4\" up=\"0 1 0\"/>"
                              "</transform></shape></scene>");
  const XmlDocument doc(path, {});
  const glm::dmat4 m = parseTransform(doc, doc.root().children.at(0).children.at(0));
  // Mitsuba's frame: +z towards the target, +y up, +x = up x dir = (1, 0, 0) x ... = left.
  EXPECT_EQ(glm::dvec3(m[2]), glm::dvec3(0, 0, 1));
  EXPECT_EQ(glm::dvec3(m[1]), glm::dvec3(0, 1, 0));
  EXPECT_EQ(glm::dvec3(m[0]), glm::dvec3(1, 0, 0));
  EXPECT_EQ(glm::dvec3(m[3]), glm::dvec3(1, 2, 3));
  EXPECT_EQ(splitValueList("1, 2 ,3\t4"), (std::vector<std::string>{"1", "2", "3", "4"}));
}

// ---- sensor, film, sampler, integrator ----

TEST_F(MitsubaXml, CameraPoseFromToWorld) {
  const MitsubaScene m = load(sceneWith(kLight, "<float name=\"fov\" value=\"40\"/>"));
  const Camera& c = m.scene.camera;
  EXPECT_EQ(c.type, CameraType::Perspective);
  EXPECT_EQ(c.position, glm::vec3(0, 0, 5));
  expectNear(c.lookAt, {0, 0, 4});
  expectNear(c.up, {0, 1, 0});
  EXPECT_EQ(c.width, 32u);
  EXPECT_EQ(c.height, 16u);
}

// fov along x, y, the diagonal, the smaller or the larger side, or a 35 mm focal length, all as
// vktg's vertical field of view for the 32 x 16 film (aspect 2).
TEST_F(MitsubaXml, FieldOfViewAxesBecomeTheVerticalFieldOfView) {
  const double t = std::tan(30.0 * kPi / 180.0);  // fov 60: the tangent of half of it
  auto vertical = [](double halfTangent) { return 2.0 * std::atan(halfTangent) * 180.0 / kPi; };
  const double diagonal = std::sqrt(32.0 * 32.0 + 16.0 * 16.0);
  const struct {
    std::string properties;
    double fovY;
  } cases[] = {
      {"<float name=\"fov\" value=\"60\"/>", vertical(t / 2)},  // the default axis is x
      {"<float name=\"fov\" value=\"60\"/><string name=\"fov_axis\" value=\"x\"/>", vertical(t / 2)},
      {"<float name=\"fov\" value=\"60\"/><string name=\"fov_axis\" value=\"y\"/>", 60.0},
      {"<float name=\"fov\" value=\"60\"/><string name=\"fov_axis\" value=\"diagonal\"/>", vertical(t * 16 / diagonal)},
      {"<float name=\"fov\" value=\"60\"/><string name=\"fov_axis\" value=\"smaller\"/>", 60.0},
      {"<float name=\"fov\" value=\"60\"/><string name=\"fov_axis\" value=\"larger\"/>", vertical(t / 2)},
      // 50 mm on a 36 x 24 mm frame: the diagonal's half tangent is sqrt(36^2 + 24^2) / 100.
      {"", vertical(std::sqrt(36.0 * 36 + 24 * 24) / 100 * 16 / diagonal)},
      {"<string name=\"focal_length\" value=\"25mm\"/>", vertical(std::sqrt(36.0 * 36 + 24 * 24) / 50 * 16 / diagonal)},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.properties);
    EXPECT_NEAR(load(sceneWith(kLight, c.properties)).scene.camera.fovY, c.fovY, 1e-4);
  }
}

TEST_F(MitsubaXml, MaxDepthCountsSegmentsAsVktgDoes) {
  auto depths = [&](const std::string& integrator) {
    const RenderSettings r = load(sceneWith(kLight, "", integrator)).scene.render;
    return std::pair(r.maxDepth, r.rouletteDepth);
  };
  EXPECT_EQ(depths("<integrator type=\"path\"><integer name=\"max_depth\" value=\"2\"/></integrator>"), std::pair(2u, 5u));
  EXPECT_EQ(depths("<integrator type=\"path\"><integer name=\"max_depth\" value=\"-1\"/>"
                   "<integer name=\"rr_depth\" value=\"3\"/></integrator>"),
            std::pair(1024u, 3u));
  EXPECT_EQ(depths("<integrator type=\"path\"/>"), std::pair(1024u, 5u));  // the C++ path tracer: no limit
  EXPECT_EQ(depths(""), std::pair(1024u, 5u));                              // no integrator: Mitsuba's path
  EXPECT_EQ(depths("<integrator type=\"path\"><integer name=\"max_depth\" value=\"5000\"/></integrator>"), std::pair(1024u, 5u));
}

TEST_F(MitsubaXml, SamplerAndFilmSettings) {
  const std::string film = "<film type=\"transient_hdr_film\"><integer name=\"width\" value=\"8\"/>"
                           "<integer name=\"height\" value=\"4\"/><integer name=\"temporal_bins\" value=\"20\"/>"
                           "<float name=\"bin_width_opl\" value=\"0.05\"/><float name=\"start_opl\" value=\"1.6\"/>"
                           "<rfilter type=\"box\"/></film>";
  std::string text = sceneWith(kLight, "<sampler type=\"stratified\"><integer name=\"sample_count\" value=\"100\"/>"
                                       "<integer name=\"seed\" value=\"7\"/><boolean name=\"jitter\" value=\"true\"/></sampler>",
                               "<integrator type=\"transient_path\"/>");
  text.replace(text.find("<film"), text.find("</film>") + 7 - text.find("<film"), film);
  const Scene s = load(text).scene;
  EXPECT_EQ(s.render.spp, 100u);
  EXPECT_EQ(s.render.seed, 7u);
  EXPECT_EQ(s.render.maxDepth, 6u);  // mitransient's integrators stop at 6 by default
  EXPECT_EQ(s.gate.type, GateType::Bins);
  EXPECT_EQ(s.gate.binCount, 20u);
  EXPECT_DOUBLE_EQ(s.gate.binWidth, 0.05);
  EXPECT_DOUBLE_EQ(s.gate.binStart, 1.6);
  EXPECT_EQ(s.camera.width, 8u);
  EXPECT_EQ(s.camera.height, 4u);
  // One bin is a box gate over it.
  std::string one = text;
  one.replace(one.find("value=\"20\""), 10, "value=\"1\"");
  const Gate box = load(one).scene.gate;
  EXPECT_EQ(box.type, GateType::Box);
  EXPECT_DOUBLE_EQ(box.a, 1.6);
  EXPECT_DOUBLE_EQ(box.b, 1.65);
  // An hdrfilm is steady; the default sampler takes 4 samples.
  const Scene steady = load(sceneWith(kLight)).scene;
  EXPECT_EQ(steady.gate.type, GateType::Steady);
  EXPECT_EQ(steady.render.spp, 4u);
}

// ---- defaults, $name, -D ----

TEST_F(MitsubaXml, DefaultsSubstituteAndDefinesOverrideThem) {
  const std::string text = sceneWith("<default name=\"r\" value=\"0.25\"/><default name=\"rr\" value=\"0.75\"/>"
                                     "<shape type=\"rectangle\" id=\"s_$r\"><bsdf type=\"diffuse\">"
                                     "<float name=\"reflectance\" value=\"$rr\"/></bsdf></shape>" + kLight);
  const Scene byDefault = load(text).scene;
  EXPECT_EQ(byDefault.shapes[0].name, "s_0.25");  // $r is not taken as a prefix of $rr: longest names first
  EXPECT_FLOAT_EQ(byDefault.materials[0].albedo, 0.75f);
  const Scene defined = load(text, {{"rr", "0.5"}}).scene;
  EXPECT_FLOAT_EQ(defined.materials[0].albedo, 0.5f);
  EXPECT_EQ(defined.shapes[0].name, "s_0.25");
  // loadScene passes defines on; other formats refuse them.
  EXPECT_FLOAT_EQ(loadScene(m_dir / "scene.xml", {{"rr", "0.125"}}).materials.at(0).albedo, 0.125f);
  // "\$" is a literal '$'.
  EXPECT_EQ(load(sceneWith("<shape type=\"cube\" id=\"a\\$b\"/>" + kLight)).scene.shapes[0].name, "a$b");
  expectError([&] { loadScene(kScenes / "cornell_box.json", {{"a", "1"}}); }, {"-D a", "Mitsuba XML"});
}

TEST_F(MitsubaXml, UndefinedAndUnusedParametersAreErrors) {
  const std::string text = sceneWith("<shape type=\"cube\" id=\"$missing\"/>" + kLight);
  expectRefused(text, "$missing", "<shape type=\"cube\"", {"undefined parameter $missing"});
  const fs::path path = write("scene.xml", sceneWith(kLight));
  expectError([&] { loadMitsubaXml(path, {{"spp", "16"}}); }, {path.string(), "-D spp", "uses no $spp"});
  expectError([&] { loadMitsubaXml(path, {{"a-b", "1"}}); }, {"-D a-b", "letters, digits"});
}

// ---- include and ref ----

TEST_F(MitsubaXml, IncludesResolveAgainstTheIncludingFile) {
  write("parts/materials.xml", "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"grey\">"
                               "<float name=\"reflectance\" value=\"0.3\"/></bsdf>"
                               "<include filename=\"deeper/light.xml\"/></scene>");
  write("parts/deeper/light.xml", "<emitter version=\"3.0.0\" type=\"point\" id=\"bulb\">"
                                  "<float name=\"intensity\" value=\"2\"/></emitter>");
  const Scene s = load(sceneWith("<include filename=\"parts/materials.xml\"/>"
                                 "<shape type=\"cube\"><ref id=\"grey\"/></shape>"))
                      .scene;
  ASSERT_EQ(s.pointLights.size(), 1u);
  EXPECT_EQ(s.pointLights[0].name, "bulb");
  EXPECT_FLOAT_EQ(s.pointLights[0].intensity, 2.0f);
  EXPECT_FLOAT_EQ(s.materials.at(s.shapes[0].material).albedo, 0.3f);
  EXPECT_EQ(s.materials.at(s.shapes[0].material).name, "grey");
}

TEST_F(MitsubaXml, IncludeCyclesAndMissingFilesAreErrors) {
  write("a.xml", "<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/></scene>");
  write("b.xml", "<scene version=\"3.0.0\">\n\n<include filename=\"a.xml\"/></scene>");
  const std::string text = sceneWith("<include filename=\"a.xml\"/>" + kLight);
  const fs::path b = m_dir / "b.xml";
  expectError([&] { load(text); }, {b.string() + ":3: <include>", "include cycle", "a.xml -> ", "b.xml -> "});
  expectRefused(sceneWith("<include filename=\"nowhere.xml\"/>" + kLight), "nowhere", "<include>", {"nowhere.xml"});
}

TEST_F(MitsubaXml, RefsShareOneMaterialAndMayComeBeforeTheirTarget) {
  const Scene s = load(sceneWith("<shape type=\"cube\" id=\"a\"><ref id=\"m\" name=\"bsdf\"/></shape>"
                                 "<shape type=\"cube\" id=\"b\"><ref id=\"m\"/></shape>"
                                 "<bsdf type=\"diffuse\" id=\"m\"><rgb name=\"reflectance\" value=\"0.2 0.4 0.6\"/></bsdf>"
                                 "<shape type=\"cube\" id=\"c\"/>" + kLight))
                      .scene;
  ASSERT_EQ(s.shapes.size(), 3u);
  EXPECT_EQ(s.shapes[0].material, s.shapes[1].material);
  EXPECT_FLOAT_EQ(s.materials[s.shapes[0].material].albedo, 0.4f);  // the mean of r, g, b
  // No BSDF: Mitsuba's diffuse 0.5.
  const Material& fallback = s.materials[s.shapes[2].material];
  EXPECT_EQ(fallback.type, MaterialType::Diffuse);
  EXPECT_FLOAT_EQ(fallback.albedo, 0.5f);
  EXPECT_EQ(s.materials.size(), 2u);
}

// ---- BSDFs ----

TEST_F(MitsubaXml, BsdfsMapOntoVktgMaterials) {
  const Scene s = load(sceneWith(
      "<shape type=\"cube\" id=\"mirror\"><bsdf type=\"conductor\"/></shape>"
      "<shape type=\"cube\" id=\"metal\"><bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>"
      "<float name=\"alpha\" value=\"0.3\"/><rgb name=\"eta\" value=\"0.2, 0.9, 1.1\"/><rgb name=\"k\" value=\"3 2.5 2\"/>"
      "<float name=\"specular_reflectance\" value=\"0.5\"/></bsdf></shape>"
      "<shape type=\"cube\" id=\"glass\"><bsdf type=\"dielectric\"><string name=\"int_ior\" value=\"water\"/></bsdf></shape>"
      "<shape type=\"cube\" id=\"frosted\"><bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"GGX\"/>"
      "<float name=\"int_ior\" value=\"1.8\"/><float name=\"ext_ior\" value=\"1.2\"/>"
      "<float name=\"alpha_u\" value=\"0.0001\"/><float name=\"alpha_v\" value=\"0.0001\"/></bsdf></shape>"
      "<shape type=\"cube\" id=\"paper\"><bsdf type=\"twosided\"><bsdf type=\"diffuse\">"
      "<spectrum name=\"reflectance\" value=\"400:0.1, 500:0.2, 600:0.6\"/></bsdf></bsdf></shape>" + kLight))
                      .scene;
  auto material = [&](size_t shape) { return s.materials[s.shapes[shape].material]; };
  // Mitsuba's default conductor (eta 0, k 1) reflects everything; smooth is vktg's smoothest.
  EXPECT_EQ(material(0).type, MaterialType::Conductor);
  EXPECT_FLOAT_EQ(material(0).albedo, 1.0f);
  EXPECT_FLOAT_EQ(material(0).roughness, 1e-3f);
  // Normal-incidence reflectance ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) per channel, tinted, averaged.
  double f0 = 0;
  for (auto [eta, k] : {std::pair(0.2, 3.0), std::pair(0.9, 2.5), std::pair(1.1, 2.0)})
    f0 += ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k) / 3;
  EXPECT_NEAR(material(1).albedo, 0.5 * f0, 1e-6);
  EXPECT_FLOAT_EQ(material(1).roughness, 0.3f);
  EXPECT_EQ(material(2).type, MaterialType::Dielectric);
  EXPECT_NEAR(material(2).ior, 1.3330 / 1.000277, 1e-6);  // water in air (Mitsuba's default exterior)
  EXPECT_FLOAT_EQ(material(2).roughness, 1e-3f);
  EXPECT_FLOAT_EQ(material(2).albedo, 1.0f);
  EXPECT_NEAR(material(3).ior, 1.5, 1e-6);
  EXPECT_FLOAT_EQ(material(3).roughness, 1e-3f);  // alpha below vktg's smoothest becomes it
  EXPECT_EQ(material(4).type, MaterialType::Diffuse);
  EXPECT_NEAR(material(4).albedo, 0.3, 1e-6);  // the spectrum's mean
  EXPECT_EQ(material(4).name, "paper_bsdf");
}

// ---- shapes and emitters ----

TEST_F(MitsubaXml, DiskSphereAndFlippedNormals) {
  const Scene s = load(sceneWith(
      "<shape type=\"disk\"><transform name=\"to_world\"><scale value=\"2\"/></transform></shape>"
      "<shape type=\"sphere\"><point name=\"center\" x=\"1\" y=\"2\" z=\"3\"/><float name=\"radius\" value=\"0.5\"/></shape>"
      "<shape type=\"rectangle\"><boolean name=\"flip_normals\" value=\"true\"/></shape>"
      "<shape type=\"sphere\"><transform name=\"to_world\"><scale value=\"2\"/><translate x=\"-1\"/></transform>"
      "<float name=\"radius\" value=\"0.5\"/></shape>" + kLight))
                      .scene;
  const Shape& disk = s.shapes[0];
  EXPECT_EQ(disk.triangles.size(), 64u);
  EXPECT_NEAR(meshArea(disk.positions, disk.triangles), 4 * 32 * std::sin(2 * kPi / 64), 1e-4);
  for (size_t t = 0; t < disk.triangles.size(); ++t) expectNear(frontNormal(disk, t), {0, 0, 1});
  const Shape& ball = s.shapes[1];
  EXPECT_EQ(ball.triangles.size(), 5120u);
  for (const glm::vec3& p : ball.positions) EXPECT_NEAR(glm::distance(p, glm::vec3(1, 2, 3)), 0.5f, 1e-6f);
  for (size_t t = 0; t < ball.triangles.size(); ++t) {
    const glm::uvec3 tri = ball.triangles[t];
    EXPECT_GT(glm::dot(frontNormal(ball, t), ball.positions[tri.x] - glm::vec3(1, 2, 3)), 0.0f) << "outward";
  }
  for (size_t t = 0; t < 2; ++t) expectNear(frontNormal(s.shapes[2], t), {0, 0, -1});
  // to_world * translate(center) * scale(radius): radius 1 about (-1, 0, 0).
  for (const glm::vec3& p : s.shapes[3].positions) EXPECT_NEAR(glm::distance(p, glm::vec3(-1, 0, 0)), 1.0f, 1e-6f);
}

TEST_F(MitsubaXml, AreaAndPointEmitters) {
  const Scene s = load(sceneWith(
      "<shape type=\"rectangle\" id=\"panel\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"3, 6, 9\"/></emitter></shape>"
      "<shape type=\"disk\"><emitter type=\"angulararea\"><float name=\"radiance\" value=\"2\"/>"
      "<float name=\"cutoff_angle\" value=\"90\"/></emitter></shape>"
      "<emitter type=\"point\" id=\"bulb\"><point name=\"position\" value=\"1 2 3\"/><rgb name=\"intensity\" value=\"4\"/></emitter>"
      "<emitter type=\"point\"><transform name=\"to_world\"><translate value=\"0 5 0\"/></transform></emitter>"))
                      .scene;
  EXPECT_FLOAT_EQ(s.shapes[0].emission, 6.0f);
  EXPECT_FLOAT_EQ(s.shapes[1].emission, 2.0f);
  ASSERT_EQ(s.pointLights.size(), 2u);
  EXPECT_EQ(s.pointLights[0].name, "bulb");
  EXPECT_EQ(s.pointLights[0].position, glm::vec3(1, 2, 3));
  EXPECT_FLOAT_EQ(s.pointLights[0].intensity, 4.0f);
  EXPECT_EQ(s.pointLights[1].position, glm::vec3(0, 5, 0));
  EXPECT_FLOAT_EQ(s.pointLights[1].intensity, 1.0f);  // Mitsuba's default
  EXPECT_EQ(s.pointLights[1].name, "point_1");
}

TEST_F(MitsubaXml, MeshFilesLoadRelativeToTheSceneFile) {
  const MitsubaScene m = loadMitsubaXml(kData / "nlos_confocal.xml", {});
  const Shape& hidden = m.scene.shapes.at(0);
  EXPECT_EQ(hidden.name, "hidden");
  EXPECT_EQ(hidden.positions.size(), 6u);
  EXPECT_EQ(hidden.triangles.size(), 4u);
  for (size_t t = 0; t < hidden.triangles.size(); ++t) EXPECT_GT(frontNormal(hidden, t).y, 0.5f);
}

// The feature scene (a fuzzing seed too): an include of materials that refer back to the including
// file's defaults, a mesh file beside another folder, every shape kind.
TEST_F(MitsubaXml, FeatureSceneLoads) {
  const Scene s = loadScene(kData / "features.xml", {{"metal_alpha", "0.4"}});
  ASSERT_EQ(s.shapes.size(), 5u);
  EXPECT_EQ(s.materials.at(s.shapes[0].material).name, "paper");
  EXPECT_NEAR(s.materials.at(s.shapes[0].material).albedo, 0.5, 1e-6);
  EXPECT_FLOAT_EQ(s.materials.at(s.shapes[1].material).roughness, 0.4f);  // $metal_alpha, defined
  EXPECT_NEAR(s.materials.at(s.shapes[2].material).ior, 1.5 / 1.000277, 1e-6);
  EXPECT_GT(s.shapes[3].triangles.size(), 0u);
  EXPECT_FLOAT_EQ(s.shapes[4].emission, 8.0f);
  ASSERT_EQ(s.pointLights.size(), 1u);
  EXPECT_EQ(s.camera.width, 48u);
  EXPECT_NEAR(s.camera.fovY, 45.0f, 1e-4f);  // the smaller side of a 48 x 32 film is its height
  EXPECT_EQ(s.render.spp, 16u);
  EXPECT_EQ(s.render.maxDepth, 8u);
}

// ---- NLOS capture meter ----

// The confocal example: an 8 x 8 grid over the wall's uv, the sensor and the laser at each point
// facing the wall's front (down), no legs outside the scene counted.
TEST_F(MitsubaXml, ConfocalCaptureMeterIsAScanOfTheWallGrid) {
  const MitsubaScene m = loadMitsubaXml(kData / "nlos_confocal.xml", {});
  ASSERT_TRUE(m.capture);
  const Scan& scan = *m.capture;
  EXPECT_TRUE(scan.grid);
  EXPECT_EQ(scan.columns, 8u);
  EXPECT_EQ(scan.rows, 8u);
  ASSERT_EQ(scan.views.size(), 64u);
  const Scene& s = m.scene;
  EXPECT_EQ(s.camera.type, CameraType::PointSensor);
  ASSERT_EQ(s.pointLights.size(), 1u);
  EXPECT_EQ(s.pointLights[0].name, "laser");
  // The wall: scale 0.5, then 90 degrees about x (local y -> world z), at y = 1.
  for (uint32_t j = 0; j < 8; ++j)
    for (uint32_t i = 0; i < 8; ++i) {
      const SceneView& v = scan.views[j * 8 + i];
      const glm::vec3 expected(0.5f * (2 * (i + 0.5f) / 8 - 1), 1.0f, 0.5f * (2 * (j + 0.5f) / 8 - 1));
      expectNear(*v.position, expected);
      expectNear(*v.normal, {0, -1, 0});
      ASSERT_EQ(v.lightPositions.size(), 1u);
      EXPECT_EQ(v.lightPositions[0].first, 0u);
      EXPECT_EQ(v.lightPositions[0].second, *v.position);
      EXPECT_EQ(v.pathOffset, 0.0f);
    }
  EXPECT_EQ(s.camera.position, *scan.views[0].position);
  EXPECT_EQ(s.pointLights[0].position, *scan.views[0].position);
  // mitransient's max_depth 4 counts the legs to the wall and back: 2 segments in the scene.
  EXPECT_EQ(s.render.maxDepth, 2u);
  EXPECT_EQ(s.render.rouletteDepth, 3u);
  EXPECT_EQ(s.gate.type, GateType::Bins);
  EXPECT_EQ(s.render.spp, 64u);
  // The laser: albedo^2 P / pi^2 with P = pi E A, A = 4 tan^2(0.1 degrees); the wall's albedo is 1.
  const double halfTan = std::tan(0.1 * kPi / 180);
  EXPECT_NEAR(s.pointLights[0].intensity, 4 * halfTan * halfTan / kPi, 1e-12);
  // Overrides reach the grid.
  EXPECT_EQ(loadMitsubaXml(kData / "nlos_confocal.xml", {{"grid", "3"}}).capture->views.size(), 9u);
}

std::string nlosScene(const std::string& meterProperties, const std::string& wallBsdf = "<bsdf type=\"diffuse\"/>",
                      const std::string& integrator = "<integrator type=\"transient_nlos_path\"/>",
                      const std::string& film = "<film type=\"transient_hdr_film\"><integer name=\"width\" value=\"4\"/>"
                                                "<integer name=\"height\" value=\"2\"/></film>") {
  return "<scene version=\"3.0.0\">\n" + integrator +
         "\n<shape type=\"rectangle\">\n" + wallBsdf +
         "\n<transform name=\"to_world\"><scale x=\"2\"/></transform>\n<sensor type=\"nlos_capture_meter\">\n" +
         "<emitter type=\"projector\"><float name=\"irradiance\" value=\"3\"/><float name=\"fov\" value=\"1\"/></emitter>\n" +
         meterProperties + "\n" + film + "\n</sensor>\n</shape>\n</scene>\n";
}

// Non-confocal: the laser stays at laser_lookat_pixel's point (pixel / film size on the uv, as
// mitransient maps it); account_first_and_last_bounces adds both legs to each view's paths.
TEST_F(MitsubaXml, NonConfocalCaptureKeepsTheLaserAndCountsTheLegs) {
  const glm::dvec3 sensorOrigin(0.5, -1, 3), laserOrigin(-1, 2, 1);
  const MitsubaScene m = load(nlosScene(
      "<boolean name=\"account_first_and_last_bounces\" value=\"true\"/>"
      "<point name=\"sensor_origin\" x=\"0.5\" y=\"-1\" z=\"3\"/><point name=\"laser_origin\" value=\"-1 2 1\"/>"
      "<point name=\"laser_lookat_pixel\" x=\"1\" y=\"2\" z=\"0\"/>",
      "<bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"0.5\"/></bsdf>"));
  ASSERT_TRUE(m.capture);
  const Scene& s = m.scene;
  // uv (1/4, 2/2) on the wall [-2, 2] x [-1, 1] at z = 0.
  const glm::dvec3 spot(2 * (2 * 0.25 - 1), 1, 0);
  expectNear(s.pointLights.at(0).position, glm::vec3(spot));
  const double halfTan = std::tan(0.5 * kPi / 180);
  EXPECT_NEAR(s.pointLights[0].intensity, 0.25 * 3 * 4 * halfTan * halfTan / kPi, 1e-9);
  ASSERT_EQ(m.capture->views.size(), 8u);
  for (uint32_t j = 0; j < 2; ++j)
    for (uint32_t i = 0; i < 4; ++i) {
      const SceneView& v = m.capture->views[j * 4 + i];
      const glm::dvec3 p(2 * (2 * (i + 0.5) / 4 - 1), 2 * (j + 0.5) / 2 - 1, 0);
      expectNear(*v.position, glm::vec3(p));
      expectNear(*v.normal, {0, 0, 1});
      EXPECT_TRUE(v.lightPositions.empty());
      EXPECT_NEAR(v.pathOffset, glm::distance(sensorOrigin, p) + glm::distance(laserOrigin, spot), 1e-5);
    }
  EXPECT_EQ(s.render.maxDepth, 4u);  // transient_nlos_path's default 6, less the two legs
}

TEST_F(MitsubaXml, CaptureFromBehindATwoSidedWallFacesTheSensor) {
  const MitsubaScene m = load(nlosScene(
      "<boolean name=\"confocal\" value=\"true\"/><point name=\"sensor_origin\" value=\"0 0 -2\"/>"
      "<point name=\"laser_origin\" value=\"0 0 -2\"/>",
      "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/></bsdf>",
      "<integrator type=\"transient_nlos_path\"><boolean name=\"account_first_and_last_bounces\" value=\"false\"/></integrator>"));
  for (const SceneView& v : m.capture->views) expectNear(*v.normal, {0, 0, -1});
}

// ---- refusals ----

TEST_F(MitsubaXml, UnsupportedContentNamesFileLineAndElement) {
  const struct {
    std::string body, marker, element;
    std::vector<std::string> parts;
  } cases[] = {
      {"<shape type=\"cylinder\"/>", "cylinder", "<shape type=\"cylinder\">", {"unsupported shape"}},
      {"<shape type=\"cube\"><float name=\"radius\" value=\"1\"/></shape>", "radius", "<float name=\"radius\">",
       {"not a property vktg reads for <shape type=\"cube\">"}},
      {"<shape type=\"obj\"/>", "type=\"obj\"", "<shape type=\"obj\">", {"filename"}},
      {"<shape type=\"obj\"><string name=\"filename\" value=\"none.obj\"/></shape>", "none.obj", "<string name=\"filename\">",
       {"none.obj"}},
      {"<shape type=\"cube\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\"/></bsdf></shape>", "bitmap",
       "<texture type=\"bitmap\" name=\"reflectance\">", {"textures are not supported"}},
      {"<shape type=\"cube\"><bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"1.5\"/></bsdf></shape>", "1.5",
       "<float name=\"reflectance\">", {"[0, 1]"}},
      {"<shape type=\"cube\"><bsdf type=\"roughconductor\"/></shape>", "roughconductor", "<bsdf type=\"roughconductor\">",
       {"beckmann", "ggx"}},
      {"<shape type=\"cube\"><bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/></bsdf></shape>", "Au",
       "<string name=\"material\">", {"eta and k"}},
      {"<shape type=\"cube\"><bsdf type=\"plastic\"/></shape>", "plastic", "<bsdf type=\"plastic\">", {"unsupported BSDF"}},
      {"<shape type=\"cube\"><bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"conductor\"/></bsdf></shape>",
       "type=\"conductor\"", "<bsdf type=\"conductor\">", {"different BSDF per side"}},
      {"<shape type=\"cube\"><bsdf type=\"dielectric\"><float name=\"int_ior\" value=\"1\"/></bsdf></shape>", "dielectric",
       "<bsdf type=\"dielectric\">", {"int_ior / ext_ior > 1"}},
      {"<shape type=\"cube\"><ref id=\"nothing\"/></shape>", "nothing", "<ref id=\"nothing\">", {"no element has id"}},
      {"<emitter type=\"envmap\"/>", "envmap", "<emitter type=\"envmap\">", {"unsupported emitter"}},
      {"<emitter type=\"constant\"/>", "constant", "<emitter type=\"constant\">", {"unsupported emitter"}},
      {"<emitter type=\"projector\"/>", "projector", "<emitter type=\"projector\">", {"nlos_capture_meter"}},
      {"<shape type=\"cube\"><emitter type=\"angulararea\"><float name=\"cutoff_angle\" value=\"30\"/></emitter></shape>",
       "angulararea", "<emitter type=\"angulararea\">", {"hemisphere"}},
      {"<shape type=\"cube\"><transform name=\"to_world\"><rotate angle=\"3\"/></transform></shape>", "rotate",
       "<rotate>", {"axis is zero"}},
      {"<shape type=\"cube\"><transform name=\"to_world\"><skew x=\"1\"/></transform></shape>", "skew", "<skew>",
       {"not a transform operation"}},
      {"<shape type=\"cube\"><translate x=\"1\"/></shape>", "translate", "<translate>", {"inside a <transform"}},
      {"<shape type=\"cube\" id=\"x\"/><bsdf type=\"diffuse\" id=\"x\"/>", "<bsdf type=\"diffuse\" id=\"x\"", "<bsdf type=\"diffuse\" id=\"x\">",
       {"duplicate id", ":"}},
      {"<sensor type=\"perspective\"/>", "<sensor type=\"perspective\"/>", "<sensor type=\"perspective\">", {"one sensor"}},
      {"<medium type=\"homogeneous\"/>", "homogeneous", "<medium type=\"homogeneous\">", {"does not read"}},
      {"<shape type=\"cube\"><float name=\"a\" value=\"1\"/><float name=\"a\" value=\"2\"/></shape>", "value=\"2\"",
       "<float name=\"a\">", {"given twice"}},
      {"<shape type=\"cube\"><boolean name=\"flip_normals\" value=\"yes\"/></shape>", "yes", "<boolean name=\"flip_normals\">",
       {"true or false"}},
      {"<shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"2\"/></transform></shape>", "type=\"sphere\"",
       "<shape type=\"sphere\">", {"unevenly"}},
      {"<shape type=\"rectangle\"><transform name=\"to_world\"><scale x=\"0\"/></transform></shape>", "type=\"rectangle\"",
       "<shape type=\"rectangle\">", {"zero area"}},
      {"<frobnicate/>", "frobnicate", "<frobnicate>", {"unknown element"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.body);
    expectRefused(sceneWith(c.body + kLight), c.marker, c.element, c.parts);
  }
}

TEST_F(MitsubaXml, SensorAndIntegratorRefusals) {
  const struct {
    std::string sensorExtra, integrator, marker, element;
    std::vector<std::string> parts;
  } cases[] = {
      {"<float name=\"fov\" value=\"30\"/><string name=\"focal_length\" value=\"20mm\"/>", "<integrator type=\"path\"/>",
       "<sensor", "<sensor type=\"perspective\">", {"not both"}},
      {"<float name=\"fov\" value=\"30\"/><string name=\"fov_axis\" value=\"z\"/>", "<integrator type=\"path\"/>", "\"z\"",
       "<string name=\"fov_axis\">", {"fov_axis must be"}},
      {"<float name=\"principal_point_offset_x\" value=\"0.1\"/>", "<integrator type=\"path\"/>", "principal",
       "<float name=\"principal_point_offset_x\">", {"principal point"}},
      {"", "<integrator type=\"volpath\"/>", "volpath", "<integrator type=\"volpath\">", {"unsupported integrator"}},
      {"", "<integrator type=\"path\"><boolean name=\"hide_emitters\" value=\"true\"/></integrator>", "hide_emitters",
       "<boolean name=\"hide_emitters\">", {"not supported"}},
      {"", "<integrator type=\"path\"><integer name=\"max_depth\" value=\"0\"/></integrator>", "max_depth",
       "<integer name=\"max_depth\">", {"renders nothing"}},
      {"", "<integrator type=\"transient_path\"/>", "<film", "<film type=\"hdrfilm\">", {"transient integrator needs"}},
      {"", "<integrator type=\"transient_path\"><boolean name=\"camera_unwarp\" value=\"true\"/></integrator>", "camera_unwarp",
       "<boolean name=\"camera_unwarp\">", {"not supported"}},
      {"<sampler type=\"independent\"><integer name=\"sample_count\" value=\"0\"/></sampler>", "<integrator type=\"path\"/>",
       "sample_count", "<integer name=\"sample_count\">", {"not in [1,"}},
      {"<srf/>", "<integrator type=\"path\"/>", "<srf", "<srf>", {"unknown element"}},
      {"", "<integrator type=\"transient_nlos_path\"/>", "<integrator", "<integrator type=\"transient_nlos_path\">",
       {"account_first_and_last_bounces = true"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.sensorExtra + c.integrator);
    expectRefused(sceneWith(kLight, c.sensorExtra, c.integrator), c.marker, c.element, c.parts);
  }
  // Scale in a sensor's to_world, and a mirroring one.
  std::string scaled = sceneWith(kLight);
  scaled.replace(scaled.find("<lookat"), 0, "<scale value=\"2\"/>");
  expectRefused(scaled, "<transform", "<transform name=\"to_world\">", {"must not scale"});
  // Thin lens cameras are not read.
  std::string thin = sceneWith(kLight);
  thin.replace(thin.find("perspective"), 11, "thinlens");
  expectRefused(thin, "thinlens", "<sensor type=\"thinlens\">", {"unsupported sensor"});
}

TEST_F(MitsubaXml, CaptureMeterRefusals) {
  const std::string integratorAccounts =
      "<integrator type=\"transient_nlos_path\"><boolean name=\"account_first_and_last_bounces\" value=\"false\"/></integrator>";
  const struct {
    std::string text, marker, element;
    std::vector<std::string> parts;
  } cases[] = {
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/>"), "nlos_capture_meter", "<sensor type=\"nlos_capture_meter\">",
       {"account_first_and_last_bounces", "default changed"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/><point name=\"laser_lookat_pixel\" value=\"1 1 0\"/>", "<bsdf type=\"diffuse\"/>",
                 integratorAccounts),
       "laser_lookat_pixel", "<point name=\"laser_lookat_pixel\">", {"confocal"}},
      {nlosScene("", "<bsdf type=\"diffuse\"/>", integratorAccounts), "nlos_capture_meter", "<sensor type=\"nlos_capture_meter\">",
       {"laser_lookat_pixel or laser_lookat_3d"}},
      {nlosScene("<point name=\"laser_lookat_pixel\" value=\"9 1 0\"/>", "<bsdf type=\"diffuse\"/>", integratorAccounts),
       "laser_lookat_pixel", "<point name=\"laser_lookat_pixel\">", {"0 <= x <= 4"}},
      {nlosScene("<point name=\"laser_lookat_3d\" value=\"0 0 1\"/>", "<bsdf type=\"diffuse\"/>", integratorAccounts),
       "laser_lookat_3d", "<point name=\"laser_lookat_3d\">", {"not a point of the relay wall"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/><point name=\"sensor_origin\" value=\"0 0 -1\"/>",
                 "<bsdf type=\"diffuse\"/>", integratorAccounts),
       "sensor_origin", "<point name=\"sensor_origin\">", {"behind the relay wall"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/>", "<bsdf type=\"conductor\"/>", integratorAccounts), "<shape",
       "<shape type=\"rectangle\">", {"must be diffuse"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/>", "<bsdf type=\"diffuse\"/>",
                 "<integrator type=\"transient_nlos_path\"><boolean name=\"account_first_and_last_bounces\" value=\"false\"/>"
                 "<integer name=\"max_depth\" value=\"2\"/></integrator>"),
       "<integrator", "<integrator type=\"transient_nlos_path\">", {"legs to the wall"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/><integer name=\"original_film_width\" value=\"4\"/>",
                 "<bsdf type=\"diffuse\"/>", integratorAccounts),
       "original_film_width", "<integer name=\"original_film_width\">", {"confocal=true"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/>", "<bsdf type=\"diffuse\"/>", "<integrator type=\"path\"/>",
                 "<film type=\"hdrfilm\"/>"),
       "<integrator", "<integrator type=\"path\">", {"transient integrator"}},
      {nlosScene("<boolean name=\"confocal\" value=\"true\"/>", "<bsdf type=\"diffuse\"/>",
                 "<integrator type=\"transient_nlos_path\"><boolean name=\"account_first_and_last_bounces\" value=\"false\"/>"
                 "<integer name=\"capture_type\" value=\"3\"/></integrator>"),
       "capture_type", "<integer name=\"capture_type\">", {"single"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    expectRefused(c.text, c.marker, c.element, c.parts);
  }
  // The wall must be a rectangle.
  std::string disk = nlosScene("<boolean name=\"confocal\" value=\"true\"/>", "<bsdf type=\"diffuse\"/>", integratorAccounts);
  disk.replace(disk.find("rectangle"), 9, "disk");
  expectRefused(disk, "<shape", "<shape type=\"disk\">", {"must be a rectangle"});
}

TEST_F(MitsubaXml, DocumentLevelErrors) {
  // Syntax errors give the line of the fault.
  const std::string broken = "<scene version=\"3.0.0\">\n<shape type=\"cube\">\n</scene>\n";
  const fs::path path = write("broken.xml", broken);
  expectError([&] { loadMitsubaXml(path, {}); }, {path.string() + ":3: XML syntax error"});
  expectRefused("<scene version=\"0.6.0\"></scene>", "scene", "<scene>", {"versions 2.x and 3.x"});
  expectRefused("<scene></scene>", "scene", "<scene>", {"missing version"});
  expectRefused("<shape version=\"3.0.0\" type=\"cube\"/>", "shape", "<shape type=\"cube\">", {"root element"});
  expectRefused("<scene version=\"3.0.0\">\n" + kLight + "</scene>", "<scene", "<scene>", {"no sensor"});
  expectRefused(sceneWith("<shape type=\"cube\"/>"), "<scene", "<scene>", {"no emitter"});
  expectRefused(sceneWith("<ref id=\"x\"/><bsdf type=\"diffuse\" id=\"x\"/>" + kLight), "<ref", "<ref id=\"x\">",
                {"second time"});
  expectError([&] { loadMitsubaXml(m_dir / "absent.xml", {}); }, {"absent.xml"});
}

}  // namespace
}  // namespace vktg
