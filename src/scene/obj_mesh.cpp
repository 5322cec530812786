// Wavefront OBJ meshes through tinyobjloader (Debian's shared library, so the header is included
// without its implementation). tinyobjloader reads the vertices and faces; a pass over the same
// lines first gives each vertex and face its line number for errors (tinyobjloader's results carry
// none) and rejects what it would read without complaint although the line does not say it:
// coordinates that are missing or not numbers (it reads them as 0), vertex indices past the int
// range (it wraps them), faces with fewer than 3 vertices (it drops them) and polygons with more
// than 255 (it keeps their vertex count in a byte). Faces are read without tinyobjloader's
// triangulation, whose quads and ear clipping do not follow the fan rule; materials, normals,
// texture coordinates, lines and points are ignored.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <istream>
#include <streambuf>

#include "scene/mesh_files.h"
#include "scene/mesh_reading.h"
#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// tinyobjloader keeps a polygon's vertex count in an unsigned char when it does not triangulate.
constexpr size_t kMaxPolygonVertices = std::numeric_limits<unsigned char>::max();

// Answers every `mtllib` with no materials: positions are all this reader keeps, and a scene's
// material comes from the scene file.
class NoMaterials : public tinyobj::MaterialReader {
 public:
  bool operator()(const std::string&, std::vector<tinyobj::material_t>*, std::map<std::string, int>*, std::string*,
                  std::string*) override {
    return true;
  }
};

struct FaceLine {
  size_t line;
  std::string_view corners;  // the words after "f": "i", "i/j", "i//k" or "i/j/k" each
  size_t count;              // how many
};

// The vertex index of a face's corner word ("-3" of "-3/1/2").
std::string_view vertexIndexWord(std::string_view corner) { return corner.substr(0, corner.find('/')); }

// An istream over text without a copy of it.
class TextBuffer : public std::streambuf {
 public:
  explicit TextBuffer(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
};

// The vertex and face lines of the file, found as tinyobjloader finds them: lines end at "\n",
// "\r\n" or a lone "\r"; leading spaces and tabs are skipped; a line whose first word is "v" is a
// vertex, "f" a face, "#" starts a comment.
class ObjLines {
 public:
  ObjLines(std::string& text, const std::string& file) : m_file(file) {
    size_t line = 0;
    size_t at = 0;
    while (at < text.size()) {
      const size_t end = std::min(text.find_first_of("\r\n", at), text.size());
      ++line;
      read(text, at, end, line);
      at = end + 1;
      if (end < text.size() && text[end] == '\r' && at < text.size() && text[at] == '\n') ++at;
    }
  }

  const std::vector<size_t>& vertexLines() const { return m_vertexLines; }
  const std::vector<FaceLine>& faces() const { return m_faces; }

 private:
  void read(std::string& text, size_t begin, size_t end, size_t line) {
    const std::string_view content(text.data() + begin, end - begin);
    // tinyobjloader reads a line as a C string, so a NUL byte would end it early.
    if (content.find('\0') != std::string_view::npos) fail(line, "NUL byte in the line (OBJ is text)");
    const size_t first = content.find_first_not_of(" \t");
    if (first == std::string_view::npos || first + 1 >= content.size()) return;
    const char keyword = content[first];
    const bool word = content[first + 1] == ' ' || content[first + 1] == '\t';
    if (!word) return;
    const std::string_view rest = content.substr(first + 2);
    if (keyword == 'v') readVertex(rest, line);
    if (keyword == 'f') readFace(rest, line);
    // tinyobjloader's own `t` (tag) statements can allocate 300 KB for a 20-byte line; they are not
    // OBJ, and positions do not need them: the line becomes a comment.
    if (keyword == 't') text[begin + first] = '#';
  }

  void readVertex(std::string_view rest, size_t line) {
    const std::vector<std::string_view> words = splitWords(rest);
    if (words.size() < 3)
      fail(line, "vertex with " + std::to_string(words.size()) + " coordinates (expected x y z)");
    for (size_t k = 0; k < 3; ++k) {
      const std::optional<double> value = parseDecimalWord(words[k]);
      if (value && finiteAsFloat(*value)) continue;
      std::string problem = value ? "non-finite vertex coordinate " : "vertex coordinate ";
      problem.append(1, "xyz"[k]).append(" = ").append(quoteWord(words[k]));
      fail(line, problem + (value ? " (as a 32-bit float)" : " is not a number"));
    }
    m_vertexLines.push_back(line);
  }

  void readFace(std::string_view rest, size_t line) {
    const std::vector<std::string_view> corners = splitWords(rest);
    if (corners.size() < 3)
      fail(line, "face with " + std::to_string(corners.size()) + " vertices (a face needs at least 3)");
    if (corners.size() > kMaxPolygonVertices)
      fail(line, "polygon with " + std::to_string(corners.size()) + " vertices (at most " +
                     std::to_string(kMaxPolygonVertices) + " are read; split it)");
    for (const std::string_view corner : corners) {
      const std::string_view index = vertexIndexWord(corner);
      const std::optional<int64_t> value = parseIntegerWord(index);
      if (!value || *value == 0)
        fail(line, "vertex index " + quoteWord(index) +
                       " is not a non-zero integer (OBJ counts vertices from 1, or back from -1)");
      if (*value < -std::numeric_limits<int>::max() || *value > std::numeric_limits<int>::max())
        fail(line, "vertex index " + quoteWord(index) + " is beyond the 32-bit integer range");
    }
    m_faces.push_back(FaceLine{line, rest, corners.size()});
  }

  [[noreturn]] void fail(size_t line, const std::string& problem) const {
    vktg::fail(m_file, "line " + std::to_string(line), problem);
  }

  const std::string& m_file;
  std::vector<size_t> m_vertexLines;
  std::vector<FaceLine> m_faces;
};

// tinyobjloader's errors say "line N" where they know it.
[[noreturn]] void failFromTinyobj(const std::string& file, std::string err) {
  std::replace(err.begin(), err.end(), '\n', ' ');
  while (!err.empty() && err.back() == ' ') err.pop_back();
  std::string field;
  const size_t at = err.rfind("line ");
  if (at != std::string::npos) {
    size_t end = at + 5;
    while (end < err.size() && err[end] >= '0' && err[end] <= '9') ++end;
    if (end > at + 5) field = err.substr(at, end - at);
  }
  vktg::fail(file, field, "malformed OBJ: " + (err.empty() ? std::string("tinyobjloader could not read it") : err));
}

}  // namespace

TriangleMesh parseObjMesh(const std::string& bytes, const std::string& file) {
  std::string text = bytes;
  const ObjLines lines(text, file);

  TextBuffer buffer(text);
  std::istream stream(&buffer);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  NoMaterials noMaterials;
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, &noMaterials,
                                   /*triangulate=*/false, /*default_vcols_fallback=*/false);
  if (!ok || !err.empty()) failFromTinyobj(file, err);

  const size_t vertexCount = attrib.vertices.size() / 3;
  if (vertexCount != lines.vertexLines().size())
    fail(file, "", "tinyobjloader read " + std::to_string(vertexCount) + " vertices where the file has " +
                       std::to_string(lines.vertexLines().size()) + " vertex lines");
  if (vertexCount > std::numeric_limits<uint32_t>::max())
    fail(file, "", "too many vertices: " + std::to_string(vertexCount) + " (at most 2^32 - 1)");

  TriangleMesh mesh;
  mesh.positions.resize(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i) {
    const glm::vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    // The line pass found finite numbers, but tinyobjloader's own conversion can still overflow
    // ("0e999" is 0 * 5^999 to it: NaN).
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k]))
        fail(file, "line " + std::to_string(lines.vertexLines()[i]),
             std::string("non-finite vertex coordinate ") + "xyz"[k] +
                 " (tinyobjloader reads it as NaN or infinity; write it without a huge exponent)");
    mesh.positions[i] = p;
  }

  // tinyobjloader's shapes (one per object or group, split where the material changes) hold the
  // faces in file order.
  size_t face = 0;
  std::vector<uint32_t> polygon;
  for (const tinyobj::shape_t& shape : shapes) {
    size_t corner = 0;
    for (const unsigned char count : shape.mesh.num_face_vertices) {
      if (face >= lines.faces().size())
        fail(file, "", "tinyobjloader read more faces than the file has face lines");
      const FaceLine& source = lines.faces()[face++];
      const std::string where = "line " + std::to_string(source.line);
      if (count != source.count || corner + count > shape.mesh.indices.size())
        fail(file, where, "face not understood: tinyobjloader read " + std::to_string(count) + " of its " +
                              std::to_string(source.count) + " vertices");
      polygon.clear();
      for (size_t k = 0; k < count; ++k) {
        const int index = shape.mesh.indices[corner + k].vertex_index;
        if (index < 0 || size_t(index) >= vertexCount) {
          const std::string_view word = vertexIndexWord(splitWords(source.corners)[k]);
          if (word.front() == '-')
            fail(file, where, "relative vertex index " + std::string(word) + " reaches before the first vertex (" +
                                  std::to_string(int64_t(index) - *parseIntegerWord(word)) +
                                  " vertices precede this line)");
          fail(file, where, "vertex index " + std::string(word) + " out of range (the file has " +
                                std::to_string(vertexCount) + " vertices)");
        }
        polygon.push_back(uint32_t(index));
      }
      corner += count;
      appendFan(mesh.triangles, polygon.data(), polygon.size());
    }
  }
  if (face != lines.faces().size())
    fail(file, "", "tinyobjloader read " + std::to_string(face) + " faces where the file has " +
                       std::to_string(lines.faces().size()) + " face lines");
  if (mesh.triangles.empty()) fail(file, "", "no faces: the file has no triangles (only `f` lines make them)");
  return mesh;
}

TriangleMesh loadObjMesh(const std::filesystem::path& path) { return parseObjMesh(readTextFile(path), path.string()); }

}  // namespace vktg
