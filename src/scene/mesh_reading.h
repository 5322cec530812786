// What the OBJ and PLY readers (obj_mesh.cpp, ply_mesh.cpp) share: reading numbers from the words
// of a text line, and the fan rule that turns a polygon into triangles.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace vktg {

// The words of a text line, split at spaces, tabs and carriage returns.
std::vector<std::string_view> splitWords(std::string_view line);

// A whole word as a decimal number ("-1.5", "+2", ".5e-3", "inf", "nan"), or nothing if the word
// is not one or lies outside the double range. The caller decides whether infinities and NaN are
// acceptable.
std::optional<double> parseDecimalWord(std::string_view word);
// A whole word as a decimal integer with an optional sign, or nothing if it is not one or lies
// outside the int64 range.
std::optional<int64_t> parseIntegerWord(std::string_view word);

// A word of the file for an error message: in double quotes, bytes outside printable ASCII as
// \xNN, cut after 40 characters ("..."), so that the message stays one readable line.
std::string quoteWord(std::string_view word);

// Whether a coordinate read as a double can be kept as a finite 32-bit float, the precision the
// renderer keeps positions in.
bool finiteAsFloat(double value);

// The polygon (i0, i1, ..., in-1), n >= 3, as the fan (i0, ik, ik+1) for k = 1 .. n-2: every
// triangle keeps the polygon's winding, so its front face is the polygon's front face.
void appendFan(std::vector<glm::uvec3>& triangles, const uint32_t* polygon, size_t count);

}  // namespace vktg
