#include "scene/ply_header.h"

#include <algorithm>
#include <optional>

#include "scene/mesh_reading.h"
#include "vktg/error.h"

namespace vktg {
namespace {

struct TypeName {
  std::string_view name;
  PlyType type;
};

// The PLY 1.0 names and the sized aliases most writers use today.
constexpr TypeName kTypeNames[] = {
    {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
    {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
    {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
    {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
    {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
    {"float64", PlyType::Float64},
};

class HeaderParser {
 public:
  HeaderParser(std::string_view bytes, const std::string& file) : m_bytes(bytes), m_file(file) {}

  PlyHeader parse() {
    if (!m_bytes.starts_with("ply\n") && !m_bytes.starts_with("ply\r\n"))
      vktg::fail(m_file, "", "not a PLY file: it does not start with a \"ply\" line");
    bool haveFormat = false;
    for (;;) {
      const size_t end = m_bytes.find('\n', m_at);
      if (end == std::string_view::npos)
        vktg::fail(m_file, "", "truncated header: no end_header line");
      std::string_view line = m_bytes.substr(m_at, end - m_at);
      m_at = end + 1;
      ++m_line;
      if (m_line == 1) continue;  // "ply"
      const std::vector<std::string_view> words = splitWords(line);
      if (words.empty()) continue;
      const std::string_view keyword = words[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      // Names and words of the header reappear in error messages.
      for (const char c : line)
        if ((c < 0x20 || c > 0x7e) && c != '\t' && c != '\r')
          fail("byte " + quoteWord(std::string_view(&c, 1)) + " is not printable ASCII (a PLY header is text)");
      if (keyword == "end_header") {
        if (words.size() != 1) fail("end_header takes nothing after it");
        break;
      }
      if (keyword == "format") {
        if (haveFormat) fail("a second format line");
        readFormat(words);
        haveFormat = true;
      } else if (keyword == "element") {
        readElement(words);
      } else if (keyword == "property") {
        readProperty(words);
      } else {
        fail("unknown header keyword " + quoteWord(keyword));
      }
    }
    if (!haveFormat) vktg::fail(m_file, "", "header without a format line");
    m_header.bodyOffset = m_at;
    m_header.lineCount = m_line;
    return std::move(m_header);
  }

 private:
  void readFormat(const std::vector<std::string_view>& words) {
    if (words.size() != 3) fail("expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
    if (words[1] == "ascii") m_header.format = PlyFormat::Ascii;
    else if (words[1] == "binary_little_endian") m_header.format = PlyFormat::BinaryLittleEndian;
    else if (words[1] == "binary_big_endian") m_header.format = PlyFormat::BinaryBigEndian;
    else fail("unknown format " + quoteWord(words[1]) + " (expected ascii, binary_little_endian or binary_big_endian)");
    if (words[2] != "1.0") fail("unsupported PLY version " + quoteWord(words[2]) + " (this reader reads 1.0)");
  }

  void readElement(const std::vector<std::string_view>& words) {
    if (words.size() != 3) fail("expected \"element NAME COUNT\"");
    PlyElement element;
    element.name = words[1];
    element.line = m_line;
    const std::optional<int64_t> count = parseIntegerWord(words[2]);
    if (!count || *count < 0)
      fail("element " + element.name + ": count " + quoteWord(words[2]) + " is not a non-negative integer");
    element.count = uint64_t(*count);
    if (m_header.find(element.name)) fail("element " + element.name + " declared twice");
    m_header.elements.push_back(std::move(element));
  }

  void readProperty(const std::vector<std::string_view>& words) {
    if (m_header.elements.empty()) fail("property before any element");
    PlyElement& element = m_header.elements.back();
    PlyProperty property;
    property.line = m_line;
    if (words.size() >= 2 && words[1] == "list") {
      if (words.size() != 5) fail("expected \"property list COUNTTYPE TYPE NAME\"");
      property.isList = true;
      property.countType = type(words[2]);
      if (!plyTypeIsIntegral(property.countType))
        fail("list length type " + quoteWord(words[2]) + " is not an integer type");
      property.type = type(words[3]);
      property.name = words[4];
    } else {
      if (words.size() != 3) fail("expected \"property TYPE NAME\" or \"property list COUNTTYPE TYPE NAME\"");
      property.type = type(words[1]);
      property.name = words[2];
    }
    if (element.find(property.name)) fail("element " + element.name + ": property " + property.name + " declared twice");
    element.properties.push_back(std::move(property));
  }

  PlyType type(std::string_view name) const {
    for (const TypeName& t : kTypeNames)
      if (t.name == name) return t.type;
    fail("unknown property type " + quoteWord(name));
  }

  [[noreturn]] void fail(const std::string& problem) const {
    vktg::fail(m_file, "header line " + std::to_string(m_line), problem);
  }

  std::string_view m_bytes;
  const std::string& m_file;
  size_t m_at = 0;
  size_t m_line = 0;
  PlyHeader m_header;
};

}  // namespace

const PlyProperty* PlyElement::find(std::string_view wanted) const {
  for (const PlyProperty& p : properties)
    if (p.name == wanted) return &p;
  return nullptr;
}

const PlyElement* PlyHeader::find(std::string_view wanted) const {
  for (const PlyElement& e : elements)
    if (e.name == wanted) return &e;
  return nullptr;
}

PlyHeader parsePlyHeader(std::string_view bytes, const std::string& file) { return HeaderParser(bytes, file).parse(); }

size_t plyTypeSize(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

const char* plyTypeName(PlyType type) {
  switch (type) {
    case PlyType::Int8: return "char";
    case PlyType::UInt8: return "uchar";
    case PlyType::Int16: return "short";
    case PlyType::UInt16: return "ushort";
    case PlyType::Int32: return "int";
    case PlyType::UInt32: return "uint";
    case PlyType::Float32: return "float";
    case PlyType::Float64: return "double";
  }
  return "?";
}

bool plyTypeIsIntegral(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

}  // namespace vktg
