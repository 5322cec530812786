// OBJ and PLY mesh files (src/scene/obj_mesh.cpp, ply_mesh.cpp; docs/scene-format.md "Mesh files").
//
// tests/data/meshes/ holds one pentagonal prism written by make_prism.py as OBJ, ASCII PLY, binary
// PLY in both byte orders, and glTF (the glTF file holds the fan triangles the readers must make
// of the polygons): every reader must give exactly kPositions and kTriangles below. The PLY files
// also carry properties and elements the reader must skip. Each bad input has its own test, which
// checks that the message names the file, where in it, and the problem.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <unistd.h>

#include <gtest/gtest.h>

#include "scene/mesh_files.h"
#include "scene/primitives.h"
#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
const fs::path kData = VKTG_TEST_DATA;
const fs::path kMeshes = kData / "meshes";

// make_prism.py: the pentagon ring at z = -0.5 (vertices 0-4) and z = 0.75 (5-9).
const std::vector<glm::vec3> kPositions = {
    {1, 0, -0.5f}, {0.5f, 1, -0.5f}, {-0.5f, 1, -0.5f}, {-1, 0, -0.5f}, {0, -1.25f, -0.5f},
    {1, 0, 0.75f}, {0.5f, 1, 0.75f}, {-0.5f, 1, 0.75f}, {-1, 0, 0.75f}, {0, -1.25f, 0.75f}};
// Faces top (5 6 7 8 9), bottom (0 4 3 2 1), sides (i, i+1, 5+i+1, 5+i), each as its fan.
const std::vector<glm::uvec3> kTriangles = {
    {5, 6, 7}, {5, 7, 8}, {5, 8, 9},                                            // top
    {0, 4, 3}, {0, 3, 2}, {0, 2, 1},                                            // bottom
    {0, 1, 6}, {0, 6, 5}, {1, 2, 7}, {1, 7, 6}, {2, 3, 8}, {2, 8, 7},           // sides
    {3, 4, 9}, {3, 9, 8}, {4, 0, 5}, {4, 5, 9}};

void expectPrism(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles) {
  ASSERT_EQ(positions.size(), kPositions.size());
  EXPECT_EQ(std::memcmp(positions.data(), kPositions.data(), positions.size() * sizeof(glm::vec3)), 0)
      << "positions differ in some bit";
  EXPECT_EQ(triangles, kTriangles);
}

// Signed volume (sum of the tetrahedra from the origin): positive when every face's front side,
// by the rule normalize(cross(p1 - p0, p2 - p0)), faces outward.
double signedVolume(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& triangles) {
  double volume = 0;
  for (const glm::uvec3& t : triangles) volume += glm::dot(p[t.x], glm::cross(p[t.y], p[t.z])) / 6.0;
  return volume;
}

std::string errorOf(const std::function<void()>& load) {
  try {
    load();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string objError(const std::string& text) {
  return errorOf([&] { parseObjMesh(text, "bad.obj"); });
}
std::string plyError(const std::string& bytes) {
  return errorOf([&] { parsePlyMesh(bytes, "bad.ply"); });
}

// The message starts with the file and contains each of `parts`.
void expectMessage(const std::string& message, const std::string& file, std::initializer_list<std::string> parts) {
  ASSERT_FALSE(message.empty()) << "accepted";
  EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
  for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
}

// A binary PLY body, value by value, in either byte order.
class Bytes {
 public:
  explicit Bytes(bool bigEndian) : m_swap(bigEndian != (std::endian::native == std::endian::big)) {}
  template <class T>
  Bytes& put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (m_swap) std::reverse(raw, raw + sizeof(T));
    m_bytes.append(raw, sizeof(T));
    return *this;
  }
  const std::string& str() const { return m_bytes; }

 private:
  bool m_swap;
  std::string m_bytes;
};

// A triangle (0, 1, 2) over three float vertices, in ASCII.
const std::string kAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kAsciiTriangle = kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

std::string binaryHeader(const std::string& format, uint64_t vertices, uint64_t faces,
                         const std::string& faceList = "uchar int") {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
         "\nproperty list " + faceList + " vertex_indices\nend_header\n";
}

// Vertices (0,0,0), (1,0,0), (0,1,0) as little-endian floats.
std::string littleEndianVertices() {
  Bytes b(false);
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put(v);
  return b.str();
}

// ---- Every format gives the same mesh.

TEST(MeshFiles, ObjGivesThePrism) {
  const TriangleMesh mesh = loadObjMesh(kMeshes / "prism.obj");
  expectPrism(mesh.positions, mesh.triangles);
}

TEST(MeshFiles, AsciiPlyGivesThePrism) {
  const TriangleMesh mesh = loadPlyMesh(kMeshes / "prism_ascii.ply");
  expectPrism(mesh.positions, mesh.triangles);
}

TEST(MeshFiles, LittleEndianPlyGivesThePrism) {
  const TriangleMesh mesh = loadPlyMesh(kMeshes / "prism_le.ply");
  expectPrism(mesh.positions, mesh.triangles);
}

TEST(MeshFiles, BigEndianPlyGivesThePrism) {
  const TriangleMesh mesh = loadPlyMesh(kMeshes / "prism_be.ply");
  expectPrism(mesh.positions, mesh.triangles);
}

std::string meshScene(const std::string& file, const std::string& shapeExtra = "") {
  return R"({"version": 1, "camera": {"type": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0]},
             "materials": {"stone": {"type": "diffuse", "albedo": 0.3}},
             "shapes": [{"name": "prism", "type": "mesh", "file": ")" +
         file + R"(", "material": "stone")" + shapeExtra + R"(},
                        {"type": "rectangle", "emission": 1, "transform": {"translate": [0, 3, 0]}}]})";
}

TEST(MeshFiles, GltfSceneMeshGivesThePrism) {
  const Scene scene = parseSceneJson(meshScene("prism.gltf"), "scene.json", kMeshes);
  expectPrism(scene.shapes[0].positions, scene.shapes[0].triangles);
}

TEST(MeshFiles, SceneMeshesFromEveryFormatAgree) {
  for (const char* file : {"prism.obj", "prism_ascii.ply", "prism_le.ply", "prism_be.ply", "prism.gltf"}) {
    SCOPED_TRACE(file);
    const Scene scene = parseSceneJson(meshScene(file), "scene.json", kMeshes);
    ASSERT_EQ(scene.shapes.size(), 2u);
    const Shape& prism = scene.shapes[0];
    EXPECT_EQ(prism.name, "prism");
    EXPECT_EQ(scene.materials[prism.material].name, "stone");
    expectPrism(prism.positions, prism.triangles);
  }
}

TEST(MeshFiles, ThePrismIsClosedAndFacesOutward) {
  // Pentagon area 2.75 (shoelace) times height 1.25.
  const TriangleMesh mesh = loadObjMesh(kMeshes / "prism.obj");
  EXPECT_NEAR(signedVolume(mesh.positions, mesh.triangles), 2.75 * 1.25, 1e-6);
}

// ---- Scenes.

TEST(MeshFiles, SceneMeshShapeTakesTransformEmissionAndName) {
  const Scene scene = parseSceneJson(
      meshScene("prism_le.ply", R"(, "emission": 2, "transform": {"translate": [0, 0, 1], "scale": [1, 1, -2]})"),
      "scene.json", kMeshes);
  const Shape& prism = scene.shapes[0];
  EXPECT_EQ(prism.name, "prism");
  EXPECT_EQ(prism.emission, 2.0f);
  ASSERT_EQ(prism.positions.size(), kPositions.size());
  for (size_t i = 0; i < kPositions.size(); ++i)
    EXPECT_EQ(prism.positions[i], glm::vec3(kPositions[i].x, kPositions[i].y, 1 - 2 * kPositions[i].z));
  // The mirroring scale reverses the winding, so the faces still point out of the (mirrored) prism.
  EXPECT_NEAR(signedVolume(prism.positions, prism.triangles), 2 * 2.75 * 1.25, 1e-5);
}

TEST(MeshFiles, SceneMeshExtensionIsCaseInsensitive) {
  const fs::path dir = fs::temp_directory_path() / ("vktg_mesh_case_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(kMeshes / "prism.obj", dir / "PRISM.OBJ", fs::copy_options::overwrite_existing);
  const Scene scene = parseSceneJson(meshScene("PRISM.OBJ"), "scene.json", dir);
  expectPrism(scene.shapes[0].positions, scene.shapes[0].triangles);
  fs::remove_all(dir);
}

TEST(MeshFiles, SceneMeshWithUnknownExtensionNamesTheFileField) {
  const std::string message = errorOf([] { parseSceneJson(meshScene("prism.stl"), "scene.json", kMeshes); });
  expectMessage(message, "scene.json", {"shapes[0].file: ", "unknown mesh file extension \".stl\"", ".obj, .ply"});
}

TEST(MeshFiles, SceneMeshReaderErrorsNameTheFieldAndTheFile) {
  const fs::path dir = fs::temp_directory_path() / ("vktg_mesh_bad_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "x.ply", std::ios::binary) << "ply\nformat ascii 1.0\nend_header\n";
  const std::string message = errorOf([&] { parseSceneJson(meshScene("x.ply"), "scene.json", dir); });
  expectMessage(message, "scene.json", {"shapes[0].file: " + (dir / "x.ply").string() + ": ", "no vertex element"});
  fs::remove_all(dir);
}

TEST(MeshFiles, SceneMeshOfZeroAreaIsAnError) {
  const fs::path dir = fs::temp_directory_path() / ("vktg_mesh_flat_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  const std::string message = errorOf([&] { parseSceneJson(meshScene("flat.obj"), "scene.json", dir); });
  expectMessage(message, "scene.json", {"shapes[0]: ", "zero area"});
  fs::remove_all(dir);
}

// ---- Polygons, indices and skipped content.

TEST(MeshFiles, PolygonsBecomeFansKeepingTheirWinding) {
  const std::string pentagon = "v 1 0 0\nv 0.5 1 0\nv -0.5 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3 4 5\n";
  const TriangleMesh obj = parseObjMesh(pentagon, "pentagon.obj");
  const std::vector<glm::uvec3> fan = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}};
  EXPECT_EQ(obj.triangles, fan);
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                          "1 0 0\n0.5 1 0\n-0.5 1 0\n-1 0 0\n0 -1 0\n5 0 1 2 3 4\n";
  EXPECT_EQ(parsePlyMesh(ply, "pentagon.ply").triangles, fan);
  // Counter-clockwise seen from +z: every triangle's front face is +z.
  for (const glm::uvec3& t : obj.triangles) {
    const glm::vec3 n = glm::cross(obj.positions[t.y] - obj.positions[t.x], obj.positions[t.z] - obj.positions[t.x]);
    EXPECT_GT(n.z, 0.0f);
  }
}

TEST(MeshFiles, ObjRelativeIndicesCountBackFromTheLine) {
  const TriangleMesh mesh =
      parseObjMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf -3 -2 -1\nf 1 -5 3\n", "r.obj");
  const std::vector<glm::uvec3> expected = {{0, 1, 2}, {3, 4, 5}, {0, 1, 2}};
  EXPECT_EQ(mesh.triangles, expected);
}

TEST(MeshFiles, ObjIndicesMayReferToLaterVertices) {
  const TriangleMesh mesh = parseObjMesh("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "forward.obj");
  EXPECT_EQ(mesh.triangles, std::vector<glm::uvec3>({{0, 1, 2}}));
}

TEST(MeshFiles, ObjKeepsEveryObjectAndGroupAndIgnoresTheRest) {
  const TriangleMesh mesh = parseObjMesh(
      "mtllib missing.mtl\no a\nv 0 0 0\nv 1 0 0\nv 0 1 0 1\nvn 0 0 1\nvt 0.5 0.5\ns 1\nusemtl red\nf 1/1/1 2/1/1 3/1/1\n"
      "l 1 2\np 3\ng b c\nusemtl blue\nf 3//1 2//1 1//1\r\n# comment\n\no d\nf 1/1 3/1 2/1\n",
      "many.obj");
  const std::vector<glm::uvec3> expected = {{0, 1, 2}, {2, 1, 0}, {0, 2, 1}};
  EXPECT_EQ(mesh.triangles, expected);
  EXPECT_EQ(mesh.positions[2], glm::vec3(0, 1, 0));  // w = 1 is not a coordinate
}

TEST(MeshFiles, PlyElementsMayComeInAnyOrder) {
  // Faces before vertices, an element without properties, another with a list of doubles.
  const std::string ply =
      "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar uint vertex_index\nelement nothing 5\n"
      "element vertex 3\nproperty int x\nproperty list int double extra\nproperty short y\nproperty char z\n"
      "end_header\n3 2 1 0\n1 2 0.5 0.25 0 0\n0 0 0 0\n0 1 1.5 1 0\n";
  const TriangleMesh mesh = parsePlyMesh(ply, "order.ply");
  EXPECT_EQ(mesh.triangles, std::vector<glm::uvec3>({{2, 1, 0}}));
  EXPECT_EQ(mesh.positions, std::vector<glm::vec3>({{1, 0, 0}, {0, 0, 0}, {0, 1, 0}}));
}

TEST(MeshFiles, PlyBinaryHeaderMayEndInCrLf) {
  std::string header = binaryHeader("binary_little_endian", 3, 1);
  std::string crlf;
  for (char c : header) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  Bytes face(false);
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  const TriangleMesh mesh = parsePlyMesh(crlf + littleEndianVertices() + face.str(), "crlf.ply");
  EXPECT_EQ(mesh.positions[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(mesh.triangles, std::vector<glm::uvec3>({{0, 1, 2}}));
}

TEST(MeshFiles, PlyReadsEveryScalarTypeAndAlias) {
  for (const auto& [type, alias] : std::vector<std::pair<std::string, std::string>>{
           {"char", "int8"}, {"uchar", "uint8"}, {"short", "int16"}, {"ushort", "uint16"},
           {"int", "int32"}, {"uint", "uint32"}, {"float", "float32"}, {"double", "float64"}}) {
    for (const std::string& name : {type, alias}) {
      SCOPED_TRACE(name);
      const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty " + name + " x\nproperty " + name +
                              " y\nproperty " + name + " z\nelement face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0\n100 0 0\n0 100 0\n3 0 1 2\n";
      EXPECT_EQ(parsePlyMesh(ply, "types.ply").positions[1], glm::vec3(100, 0, 0));
    }
  }
}

TEST(MeshFiles, PlyBytesAfterTheLastElementAreIgnored) {
  EXPECT_EQ(parsePlyMesh(kAsciiTriangle + "3 0 1 2\nnot a face\n", "t.ply").triangles.size(), 1u);
  Bytes face(false);
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2).put<uint32_t>(0xdeadbeef);
  EXPECT_EQ(parsePlyMesh(binaryHeader("binary_little_endian", 3, 1) + littleEndianVertices() + face.str(), "t.ply")
                .triangles.size(),
            1u);
}

TEST(MeshFiles, MissingFilesAreErrors) {
  expectMessage(errorOf([] { loadObjMesh(kMeshes / "nowhere.obj"); }), (kMeshes / "nowhere.obj").string(), {"not found"});
  expectMessage(errorOf([] { loadPlyMesh(kMeshes / "nowhere.ply"); }), (kMeshes / "nowhere.ply").string(), {"not found"});
}

// ---- Bad OBJ files: each names the file, the line and the problem.

TEST(MeshFilesBadObj, IndexOutOfRange) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), "bad.obj", {"line 4: ", "vertex index 4 out of range", "3 vertices"});
}

TEST(MeshFilesBadObj, ZeroIndex) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "bad.obj", {"line 4: ", "\"0\" is not a non-zero integer"});
}

TEST(MeshFilesBadObj, IndexThatIsNotANumber) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"), "bad.obj", {"line 4: ", "\"x\" is not a non-zero integer"});
}

TEST(MeshFilesBadObj, IndexPastTheIntRange) {
  // tinyobjloader would wrap 4294967297 to 1.
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 4294967297 2 3\n"), "bad.obj", {"line 4: ", "\"4294967297\" is beyond the 32-bit integer range"});
}

TEST(MeshFilesBadObj, RelativeIndexBeforeTheFirstVertex) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"), "bad.obj",
                {"line 3: ", "relative vertex index -3 reaches before the first vertex", "2 vertices precede"});
}

TEST(MeshFilesBadObj, FaceWithTwoVertices) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"), "bad.obj", {"line 4: ", "face with 2 vertices"});
}

TEST(MeshFilesBadObj, PolygonPastTinyobjloadersLimit) {
  std::string text, face = "f";
  for (int i = 1; i <= 256; ++i) {
    text += "v " + std::to_string(std::cos(i * 0.02)) + " " + std::to_string(std::sin(i * 0.02)) + " 0\n";
    face += " " + std::to_string(i);
  }
  expectMessage(objError(text + face + "\n"), "bad.obj", {"line 257: ", "polygon with 256 vertices"});
}

TEST(MeshFilesBadObj, CoordinateThatIsNotANumber) {
  // tinyobjloader would read "1,5" as 1.
  expectMessage(objError("v 0 0 0\nv 1,5 0 0\nv 0 1 0\nf 1 2 3\n"), "bad.obj", {"line 2: ", "x = \"1,5\" is not a number"});
}

TEST(MeshFilesBadObj, MissingCoordinate) {
  // tinyobjloader would read the missing z as 0.
  expectMessage(objError("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"), "bad.obj", {"line 2: ", "vertex with 2 coordinates"});
}

TEST(MeshFilesBadObj, NonFiniteCoordinate) {
  expectMessage(objError("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"), "bad.obj", {"line 2: ", "non-finite vertex coordinate z"});
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n"), "bad.obj", {"line 3: ", "non-finite vertex coordinate y"});
}

TEST(MeshFilesBadObj, NoFaces) {
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n"), "bad.obj", {"no faces"});
  expectMessage(objError(""), "bad.obj", {"no faces"});
}

TEST(MeshFilesBadObj, NulByte) {
  expectMessage(objError(std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\0 5\nf 1 2 3\n", 35)), "bad.obj", {"line 3: ", "NUL byte"});
}

TEST(MeshFilesBadObj, TinyobjloaderErrorKeepsItsLine) {
  // A zero index in a line statement: lines are ignored, but tinyobjloader refuses the file.
  expectMessage(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 0\n"), "bad.obj", {"line 5: ", "malformed OBJ"});
}

// Found by fuzzing: tinyobjloader makes NaN of a zero with a huge exponent, which the line pass
// takes for 0.
TEST(MeshFilesFuzzRegressions, ObjZeroWithHugeExponent) {
  const fs::path file = kData / "fuzz" / "obj-zero-with-huge-exponent.obj";
  expectMessage(errorOf([&] { loadObjMesh(file); }), file.string(),
                {"line 2: ", "non-finite vertex coordinate y (tinyobjloader reads it as NaN"});
}

// ---- Bad PLY files: each names the file, the header line or element, and the problem.

TEST(MeshFilesBadPly, NotAPlyFile) { expectMessage(plyError("solid cube\n"), "bad.ply", {"not a PLY file"}); }

TEST(MeshFilesBadPly, UnknownFormat) {
  expectMessage(plyError("ply\nformat binary_middle_endian 1.0\nend_header\n"), "bad.ply",
                {"header line 2: ", "unknown format \"binary_middle_endian\""});
}

TEST(MeshFilesBadPly, UnsupportedVersion) {
  expectMessage(plyError("ply\nformat ascii 2.0\nend_header\n"), "bad.ply", {"header line 2: ", "version \"2.0\""});
}

TEST(MeshFilesBadPly, UnknownPropertyType) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelement vertex 1\nproperty flaot x\nend_header\n"), "bad.ply",
                {"header line 4: ", "unknown property type \"flaot\""});
}

TEST(MeshFilesBadPly, UnknownHeaderKeyword) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n"), "bad.ply",
                {"header line 3: ", "unknown header keyword \"elemnt\""});
}

TEST(MeshFilesBadPly, NoEndHeader) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelement vertex 1\n"), "bad.ply", {"no end_header"});
}

TEST(MeshFilesBadPly, MissingCoordinate) {
  std::string header = kAsciiHeader;
  header.replace(header.find("property float z"), 16, "property float w");
  expectMessage(plyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"header line 3: ", "element vertex has no property z"});
}

TEST(MeshFilesBadPly, NoFaceElement) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n0 0 0\n"),
                "bad.ply", {"no face element"});
}

TEST(MeshFilesBadPly, FaceIndicesThatAreNotIntegers) {
  std::string header = kAsciiHeader;
  header.replace(header.find("uchar int"), 9, "uchar float");
  expectMessage(plyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"header line 8: ", "vertex_indices must be a list of integers"});
}

TEST(MeshFilesBadPly, FaceWithTwoIndices) {
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), "bad.ply",
                {"line 13: face 0: ", "2 vertex indices (a face needs at least 3)"});
  Bytes face(true);
  face.put<uint8_t>(2).put<int32_t>(0).put<int32_t>(1);
  Bytes vertices(true);
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) vertices.put(v);
  expectMessage(plyError(binaryHeader("binary_big_endian", 3, 1) + vertices.str() + face.str()), "bad.ply",
                {"face 0: ", "2 vertex indices"});
}

TEST(MeshFilesBadPly, IndexOutOfRange) {
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "bad.ply",
                {"line 13: face 0: ", "vertex index 3 out of range (the file has 3 vertices)"});
  Bytes face(false);
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(-1).put<int32_t>(2);
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1) + littleEndianVertices() + face.str()), "bad.ply",
                {"face 0: ", "vertex index -1 out of range"});
}

TEST(MeshFilesBadPly, NonFiniteCoordinate) {
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"line 11: vertex 1: ", "non-finite coordinate y"});
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 0 0\n0 1 1e39\n3 0 1 2\n"), "bad.ply",
                {"line 12: vertex 2: ", "non-finite coordinate z"});
  Bytes vertices(false);
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, std::numeric_limits<float>::infinity()}) vertices.put(v);
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1) + vertices.str()), "bad.ply",
                {"vertex 2: ", "non-finite coordinate z"});
  // A double beyond the float range.
  std::string header = binaryHeader("binary_little_endian", 3, 1);
  header.replace(header.find("float x"), 7, "double x");
  Bytes wide(false);
  for (int i = 0; i < 3; ++i) wide.put(i == 1 ? 1e300 : 0.0).put(0.f).put(0.f);
  expectMessage(plyError(header + wide.str()), "bad.ply", {"vertex 1: ", "non-finite coordinate x"});
}

TEST(MeshFilesBadPly, ValueThatIsNotANumber) {
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"line 11: vertex 1: ", "property y: \"zero\" is not a number"});
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n"), "bad.ply",
                {"line 13: face 0: ", "\"1.5\" is not an integer"});
}

TEST(MeshFilesBadPly, AsciiLineWithTooManyOrTooFewValues) {
  expectMessage(plyError(kAsciiHeader + "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"line 10: vertex 0: ", "1 values more than the element's properties"});
  expectMessage(plyError(kAsciiHeader + "0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "bad.ply",
                {"line 10: vertex 0: ", "no value for property z"});
  expectMessage(plyError(kAsciiHeader + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"), "bad.ply",
                {"line 13: face 0: ", "list of 4 items, but 3 values follow"});
}

TEST(MeshFilesBadPly, ValueOutOfRangeForItsType) {
  std::string header = kAsciiHeader;
  header.replace(header.find("uchar int"), 9, "uchar uchar");
  expectMessage(plyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 256\n"), "bad.ply",
                {"line 13: face 0: ", "\"256\" is out of range for uchar"});
}

TEST(MeshFilesBadPly, TruncatedBody) {
  // Two faces promised, one present.
  Bytes face(false);
  face.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2).put<uint8_t>(3).put<int32_t>(0);
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 2) + littleEndianVertices() + face.str()), "bad.ply",
                {"truncated body: face 1 of 2"});
  std::string header = kAsciiHeader;
  header.replace(header.find("face 1"), 6, "face 2");
  expectMessage(plyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "bad.ply", {"truncated body: face 1 of 2"});
  // The vertices cut short in the middle of one.
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1) + littleEndianVertices().substr(0, 30)), "bad.ply",
                {"truncated body"});
}

TEST(MeshFilesBadPly, HugeCountsFailBeforeAllocating) {
  // Every one of these would need terabytes if allocated from the header's count.
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1000000000000) + littleEndianVertices()), "bad.ply",
                {"truncated body: the header declares 1000000000000 face elements"});
  expectMessage(plyError(binaryHeader("binary_little_endian", 4000000000, 1)), "bad.ply",
                {"truncated body: the header declares 4000000000 vertex elements"});
  expectMessage(plyError(binaryHeader("ascii", 4000000000, 1) + "0 0 0\n"), "bad.ply",
                {"truncated body: the header declares 4000000000 vertex elements"});
  expectMessage(plyError(binaryHeader("binary_little_endian", 1000000000000, 1)), "bad.ply",
                {"header line 3: ", "too many vertices"});
  // The count of an element after a last line without a line feed.
  expectMessage(plyError("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "element vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\n"
                         "end_header\n3 0 1 2"),
                "bad.ply", {"truncated body: the header declares 4000000000 vertex elements"});
  // A list length of 4 billion indices in a 20-byte body.
  Bytes face(false);
  face.put<uint32_t>(4000000000u).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1, "uint int") + littleEndianVertices() + face.str()),
                "bad.ply", {"truncated body: face 0 of 1"});
}

TEST(MeshFilesBadPly, NegativeListLength) {
  Bytes face(false);
  face.put<int8_t>(-3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  expectMessage(plyError(binaryHeader("binary_little_endian", 3, 1, "char int") + littleEndianVertices() + face.str()),
                "bad.ply", {"face 0: ", "negative list length -3"});
}

TEST(MeshFilesBadPly, NoTriangles) {
  std::string header = kAsciiHeader;
  header.replace(header.find("face 1"), 6, "face 0");
  expectMessage(plyError(header + "0 0 0\n1 0 0\n0 1 0\n"), "bad.ply", {"no triangles"});
}

TEST(MeshFilesBadPly, HeaderThatIsNotText) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelement ver\x1btex 3\nend_header\n"), "bad.ply",
                {"header line 3: ", "byte \"\\x1b\" is not printable ASCII"});
}

TEST(MeshFilesBadPly, WordsInMessagesAreEscapedAndCut) {
  const std::string message = plyError(kAsciiHeader + "0 0 0\n1 \x01" + std::string(100, 'a') + " 0\n0 1 0\n3 0 1 2\n");
  expectMessage(message, "bad.ply", {"line 11: vertex 1: ", "\"\\x01" + std::string(39, 'a') + "...\" is not a number"});
  EXPECT_EQ(message.find('\x01'), std::string::npos) << message;
}

TEST(MeshFilesBadPly, DuplicateDeclarations) {
  expectMessage(plyError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n"),
                "bad.ply", {"header line 5: ", "property x declared twice"});
  expectMessage(plyError("ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n"), "bad.ply",
                {"header line 4: ", "element vertex declared twice"});
}

}  // namespace
}  // namespace vktg
