// The header of a Stanford PLY file: format, elements and their properties, and where the body
// starts (docs/scene-format.md, "Mesh files"). Only the header's own rules are checked here; what a
// mesh needs from it (a vertex element with x, y, z, a face element with vertex indices) is
// ply_mesh.cpp's.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace vktg {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // of a scalar, or of a list's items
  bool isList = false;
  PlyType countType = PlyType::UInt8;  // of a list's length
  size_t line = 0;                     // header line, for errors
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
  size_t line = 0;

  // The property called `name`, or nullptr.
  const PlyProperty* find(std::string_view name) const;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;  // in the order of the body
  size_t bodyOffset = 0;             // first byte after the end_header line
  size_t lineCount = 0;              // lines up to and including end_header

  const PlyElement* find(std::string_view name) const;
};

// Reads the header at the start of `bytes`; errors are "FILE: header line N: problem".
PlyHeader parsePlyHeader(std::string_view bytes, const std::string& file);

size_t plyTypeSize(PlyType type);
const char* plyTypeName(PlyType type);
bool plyTypeIsIntegral(PlyType type);

}  // namespace vktg
