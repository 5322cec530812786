// Reading the values of a Mitsuba scene's attributes: numbers and number lists as Mitsuba writes them
// (separated by spaces or commas), and <transform> elements as matrices.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "scene/mitsuba_xml_document.h"

namespace vktg {

// `text` in double quotes, for messages.
std::string quote(std::string_view text);

// The words of a value, split at spaces, tabs, line breaks and commas ("1, 2, 3" or "1 2 3").
std::vector<std::string> splitValueList(std::string_view text);
// A whole word as a finite number, or nothing.
std::optional<double> parseFiniteNumber(std::string_view text);

// Attribute `key` of `node` as a finite number; fails naming the element if it is not one.
double numberAttribute(const XmlDocument& document, const XmlNode& node, std::string_view key);
// "x y z" (or "x, y, z") as a vector; fails unless there are exactly three finite numbers.
glm::dvec3 vectorAttribute(const XmlDocument& document, const XmlNode& node, std::string_view key);

// The matrix of a <transform> element: its children (translate, rotate, scale, lookat, matrix)
// applied in Mitsuba's order, each after the ones before it (M = T_n ... T_2 T_1), in double.
// Fails naming the child on an unknown operation, a bad attribute, a zero rotation axis or a
// degenerate lookat.
glm::dmat4 parseTransform(const XmlDocument& document, const XmlNode& transform);

}  // namespace vktg
