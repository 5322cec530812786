// Stanford PLY meshes, ASCII and binary (little and big endian): the `vertex` element's x, y, z and
// the `face` element's vertex index lists; every other property and element is read past. Counts
// in the header are checked against the bytes that follow it before anything is allocated from
// them, so a header that promises more than the file holds fails at once. Bytes after the last
// element the header declares are ignored, in every format.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <limits>
#include <optional>

#include "scene/mesh_files.h"
#include "scene/mesh_reading.h"
#include "scene/ply_header.h"
#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// Which properties the mesh is built from.
struct MeshLayout {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  const PlyProperty* coordinates[3] = {nullptr, nullptr, nullptr};  // x, y, z
  const PlyProperty* indices = nullptr;
};

MeshLayout meshLayout(const PlyHeader& header, const std::string& file) {
  auto headerLine = [](size_t line) { return "header line " + std::to_string(line); };
  MeshLayout layout;
  layout.vertex = header.find("vertex");
  if (!layout.vertex) fail(file, "", "no vertex element in the header");
  for (int k = 0; k < 3; ++k) {
    const std::string name(1, "xyz"[k]);
    const PlyProperty* p = layout.vertex->find(name);
    if (!p) fail(file, headerLine(layout.vertex->line), "element vertex has no property " + name);
    if (p->isList) fail(file, headerLine(p->line), "vertex property " + name + " is a list (expected a number)");
    layout.coordinates[k] = p;
  }
  layout.face = header.find("face");
  if (!layout.face) fail(file, "", "no face element in the header: the file has no triangles");
  const PlyProperty* indices = layout.face->find("vertex_indices");
  const PlyProperty* index = layout.face->find("vertex_index");
  if (indices && index) fail(file, headerLine(index->line), "element face has both vertex_indices and vertex_index");
  layout.indices = indices ? indices : index;
  if (!layout.indices) fail(file, headerLine(layout.face->line), "element face has no property vertex_indices (or vertex_index)");
  if (!layout.indices->isList || !plyTypeIsIntegral(layout.indices->type))
    fail(file, headerLine(layout.indices->line), "face property " + layout.indices->name + " must be a list of integers");
  if (layout.vertex->count > std::numeric_limits<uint32_t>::max())
    fail(file, headerLine(layout.vertex->line), "too many vertices: " + std::to_string(layout.vertex->count) + " (at most 2^32 - 1)");
  return layout;
}

// What both body readers keep: which element instance they are in, for errors.
class BodyPosition {
 public:
  explicit BodyPosition(const std::string& file) : m_file(file) {}

  void enter(const PlyElement& element, uint64_t index) {
    m_element = &element;
    m_index = index;
  }
  std::string instance() const { return m_element->name + " " + std::to_string(m_index); }
  [[noreturn]] void truncated() const {
    fail(m_file, "", "truncated body: " + instance() + " of " + std::to_string(m_element->count) + " runs past the end of the file");
  }

 protected:
  const std::string& m_file;
  const PlyElement* m_element = nullptr;
  uint64_t m_index = 0;
};

class BinaryBody : public BodyPosition {
 public:
  BinaryBody(std::string_view bytes, size_t at, bool bigEndian, const std::string& file)
      : BodyPosition(file), m_bytes(bytes), m_at(at), m_swap(bigEndian != (std::endian::native == std::endian::big)) {}

  // Fails unless `count` instances of the element can fit in the bytes left: every scalar and every
  // list length takes its size, a list's items may be none.
  void requireRoom(const PlyElement& element) const {
    uint64_t least = 0;
    for (const PlyProperty& p : element.properties) least += plyTypeSize(p.isList ? p.countType : p.type);
    const uint64_t left = m_bytes.size() - m_at;
    if (least > 0 && element.count > left / least)
      fail(m_file, "", "truncated body: the header declares " + std::to_string(element.count) + " " + element.name +
                           " elements of at least " + std::to_string(least) + " bytes each, but " +
                           std::to_string(left) + " bytes follow the header");
  }
  void beginInstance(const PlyElement& element, uint64_t index) { enter(element, index); }
  void endInstance() {}
  std::string where() const { return instance(); }

  double real(const PlyProperty& p, PlyType type) {
    (void)p;
    unsigned char raw[8];
    take(raw, plyTypeSize(type));
    return decode(raw, type);
  }
  int64_t integer(const PlyProperty& p, PlyType type) { return int64_t(real(p, type)); }
  void skip(PlyType type) {
    if (m_bytes.size() - m_at < plyTypeSize(type)) truncated();
    m_at += plyTypeSize(type);
  }
  // A list of `count` items: fails unless they fit in the bytes left.
  void requireItems(uint64_t count, PlyType type) const {
    if (count > (m_bytes.size() - m_at) / plyTypeSize(type)) truncated();
  }
  void skipItems(uint64_t count, PlyType type) {
    requireItems(count, type);
    m_at += size_t(count) * plyTypeSize(type);
  }

 private:
  void take(unsigned char* raw, size_t size) {
    if (m_bytes.size() - m_at < size) truncated();
    std::memcpy(raw, m_bytes.data() + m_at, size);
    if (m_swap) std::reverse(raw, raw + size);
    m_at += size;
  }

  template <class T>
  static double as(const unsigned char* raw) {
    T value;
    std::memcpy(&value, raw, sizeof value);
    return double(value);
  }

  static double decode(const unsigned char* raw, PlyType type) {
    switch (type) {
      case PlyType::Int8: return as<int8_t>(raw);
      case PlyType::UInt8: return as<uint8_t>(raw);
      case PlyType::Int16: return as<int16_t>(raw);
      case PlyType::UInt16: return as<uint16_t>(raw);
      case PlyType::Int32: return as<int32_t>(raw);
      case PlyType::UInt32: return as<uint32_t>(raw);
      case PlyType::Float32: return as<float>(raw);
      case PlyType::Float64: return as<double>(raw);
    }
    return 0;
  }

  std::string_view m_bytes;
  size_t m_at;
  bool m_swap;
};

// ASCII: one element instance per line, its values separated by spaces or tabs; blank lines are
// skipped.
class AsciiBody : public BodyPosition {
 public:
  AsciiBody(std::string_view bytes, size_t at, size_t linesBefore, const std::string& file)
      : BodyPosition(file), m_bytes(bytes), m_at(at), m_line(linesBefore) {}

  // Every instance takes a line with at least one word per property: two bytes a property, less the
  // last line's line feed.
  void requireRoom(const PlyElement& element) const {
    const uint64_t least = 2 * element.properties.size();
    const uint64_t left = m_bytes.size() - m_at;
    if (least > 0 && element.count > (left + 1) / least)
      fail(m_file, "", "truncated body: the header declares " + std::to_string(element.count) + " " + element.name +
                           " elements of at least " + std::to_string(element.properties.size()) + " values each, but " +
                           std::to_string(left) + " bytes follow the header");
  }

  void beginInstance(const PlyElement& element, uint64_t index) {
    enter(element, index);
    m_words.clear();
    while (m_words.empty()) {
      if (m_at >= m_bytes.size()) truncated();
      const size_t end = std::min(m_bytes.find('\n', m_at), m_bytes.size());
      m_words = splitWords(m_bytes.substr(m_at, end - m_at));
      m_at = std::min(end + 1, m_bytes.size());  // the last line may have no line feed
      ++m_line;
    }
    m_next = 0;
  }
  void endInstance() const {
    if (m_next < m_words.size())
      fail(m_file, where(), std::to_string(m_words.size() - m_next) + " values more than the element's properties");
  }
  std::string where() const { return "line " + std::to_string(m_line) + ": " + instance(); }

  double real(const PlyProperty& p, PlyType type) {
    const std::string_view w = word(p);
    if (plyTypeIsIntegral(type)) return double(integerIn(p, w, type));
    if (type == PlyType::Float32) {
      // Read as a float directly: through a double it could round twice.
      float value = 0;
      const std::string_view digits = w.size() > 1 && w[0] == '+' ? w.substr(1) : w;
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
      if (ec == std::errc() && end == digits.data() + digits.size() && !digits.empty()) return value;
    }
    const std::optional<double> value = parseDecimalWord(w);
    if (!value) fail(m_file, where(), "property " + p.name + ": " + quoteWord(w) + " is not a number");
    return *value;  // a float32 value only comes here when it is outside the float range
  }
  int64_t integer(const PlyProperty& p, PlyType type) { return integerIn(p, word(p), type); }
  void skip(PlyType) { ++m_next; }
  void requireItems(uint64_t count, PlyType) const {
    if (count > m_words.size() - m_next)
      fail(m_file, where(), "list of " + std::to_string(count) + " items, but " + std::to_string(m_words.size() - m_next) +
                                " values follow its length");
  }
  void skipItems(uint64_t count, PlyType type) {
    requireItems(count, type);
    m_next += size_t(count);
  }

 private:
  std::string_view word(const PlyProperty& p) {
    if (m_next >= m_words.size()) fail(m_file, where(), "no value for property " + p.name);
    return m_words[m_next++];
  }

  int64_t integerIn(const PlyProperty& p, std::string_view w, PlyType type) const {
    const std::optional<int64_t> value = parseIntegerWord(w);
    if (!value) fail(m_file, where(), "property " + p.name + ": " + quoteWord(w) + " is not an integer");
    int64_t lo = 0, hi = 0;
    switch (type) {
      case PlyType::Int8: lo = INT8_MIN, hi = INT8_MAX; break;
      case PlyType::UInt8: hi = UINT8_MAX; break;
      case PlyType::Int16: lo = INT16_MIN, hi = INT16_MAX; break;
      case PlyType::UInt16: hi = UINT16_MAX; break;
      case PlyType::Int32: lo = INT32_MIN, hi = INT32_MAX; break;
      default: hi = UINT32_MAX; break;
    }
    if (*value < lo || *value > hi)
      fail(m_file, where(), "property " + p.name + ": " + quoteWord(w) + " is out of range for " + plyTypeName(type));
    return *value;
  }

  std::string_view m_bytes;
  size_t m_at;
  size_t m_line;
  std::vector<std::string_view> m_words;
  size_t m_next = 0;
};

template <class Body>
TriangleMesh readBody(Body& body, const PlyHeader& header, const MeshLayout& layout, const std::string& file) {
  TriangleMesh mesh;
  const uint64_t vertexCount = layout.vertex->count;
  std::vector<uint32_t> polygon;
  for (const PlyElement& element : header.elements) {
    body.requireRoom(element);
    if (element.properties.empty()) continue;  // nothing to read, in any format
    const bool isVertex = &element == layout.vertex;
    const bool isFace = &element == layout.face;
    if (isVertex) mesh.positions.resize(size_t(element.count));
    if (isFace) mesh.triangles.reserve(size_t(element.count));
    for (uint64_t i = 0; i < element.count; ++i) {
      body.beginInstance(element, i);
      for (const PlyProperty& p : element.properties) {
        const PlyProperty* const* coordinate = std::find(std::begin(layout.coordinates), std::end(layout.coordinates), &p);
        if (isVertex && coordinate != std::end(layout.coordinates)) {
          const double value = body.real(p, p.type);
          if (!finiteAsFloat(value))
            fail(file, body.where(), "non-finite coordinate " + p.name + " = " + formatNumber(value) + " (as a 32-bit float)");
          mesh.positions[size_t(i)][int(coordinate - std::begin(layout.coordinates))] = float(value);
        } else if (p.isList) {
          const int64_t count = body.integer(p, p.countType);
          if (count < 0) fail(file, body.where(), "property " + p.name + ": negative list length " + std::to_string(count));
          if (!(isFace && &p == layout.indices)) {
            body.skipItems(uint64_t(count), p.type);
            continue;
          }
          if (count < 3)
            fail(file, body.where(), std::to_string(count) + " vertex indices (a face needs at least 3)");
          body.requireItems(uint64_t(count), p.type);
          polygon.clear();
          for (int64_t k = 0; k < count; ++k) {
            const int64_t index = body.integer(p, p.type);
            if (index < 0 || uint64_t(index) >= vertexCount)
              fail(file, body.where(), "vertex index " + std::to_string(index) + " out of range (the file has " +
                                           std::to_string(vertexCount) + " vertices)");
            polygon.push_back(uint32_t(index));
          }
          appendFan(mesh.triangles, polygon.data(), polygon.size());
        } else {
          body.skip(p.type);
        }
      }
      body.endInstance();
    }
  }
  if (mesh.triangles.empty()) fail(file, "", "no triangles: the face element is empty");
  return mesh;
}

}  // namespace

TriangleMesh parsePlyMesh(const std::string& bytes, const std::string& file) {
  const PlyHeader header = parsePlyHeader(bytes, file);
  const MeshLayout layout = meshLayout(header, file);
  if (header.format == PlyFormat::Ascii) {
    AsciiBody body(bytes, header.bodyOffset, header.lineCount, file);
    return readBody(body, header, layout, file);
  }
  BinaryBody body(bytes, header.bodyOffset, header.format == PlyFormat::BinaryBigEndian, file);
  return readBody(body, header, layout, file);
}

TriangleMesh loadPlyMesh(const std::filesystem::path& path) { return parsePlyMesh(readTextFile(path), path.string()); }

}  // namespace vktg
