#include "scene/mitsuba_values.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <numbers>

namespace vktg {
namespace {

void allowOnly(const XmlDocument& document, const XmlNode& node, std::initializer_list<std::string_view> keys) {
  for (const auto& [key, value] : node.attributes)
    if (std::find(keys.begin(), keys.end(), key) == keys.end())
      document.fail(node, "unexpected attribute " + quote(key));
}

const std::string& required(const XmlDocument& document, const XmlNode& node, std::string_view key) {
  const std::string* value = node.attribute(key);
  if (!value) document.fail(node, "missing required attribute " + quote(key));
  return *value;
}

// x, y, z attributes (each defaulting to `fallback`) or value="a" (all three) / value="x y z".
glm::dvec3 components(const XmlDocument& document, const XmlNode& node, double fallback) {
  const std::string* value = node.attribute("value");
  if (value) {
    if (node.attribute("x") || node.attribute("y") || node.attribute("z"))
      document.fail(node, "give either value or x, y, z, not both");
    const std::vector<std::string> words = splitValueList(*value);
    if (words.size() != 1 && words.size() != 3)
      document.fail(node, "value must hold 1 or 3 numbers, not " + std::to_string(words.size()));
    glm::dvec3 v;
    for (int k = 0; k < 3; ++k) {
      const std::string& word = words[words.size() == 1 ? 0 : size_t(k)];
      const std::optional<double> number = parseFiniteNumber(word);
      if (!number) document.fail(node, "value: " + quote(word) + " is not a finite number");
      v[k] = *number;
    }
    return v;
  }
  glm::dvec3 v(fallback);
  const char* keys[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (node.attribute(keys[k])) v[k] = numberAttribute(document, node, keys[k]);
  return v;
}

// The rotation by `degrees` about `axis`, counter-clockwise looking down the axis (Rodrigues'
// formula). As in Mitsuba, the axis is used as given, not normalised.
glm::dmat4 rotation(glm::dvec3 a, double degrees) {
  const double radians = degrees * std::numbers::pi / 180.0;
  const double c = std::cos(radians), s = std::sin(radians), t = 1.0 - c;
  glm::dmat4 m(1.0);  // m[column][row]
  m[0][0] = c + t * a.x * a.x;
  m[1][0] = t * a.x * a.y - s * a.z;
  m[2][0] = t * a.x * a.z + s * a.y;
  m[0][1] = t * a.y * a.x + s * a.z;
  m[1][1] = c + t * a.y * a.y;
  m[2][1] = t * a.y * a.z - s * a.x;
  m[0][2] = t * a.z * a.x - s * a.y;
  m[1][2] = t * a.z * a.y + s * a.x;
  m[2][2] = c + t * a.z * a.z;
  return m;
}

// An up vector perpendicular to `dir` when the file gives none (Duff et al. 2017's orthonormal
// basis, the one Mitsuba uses, so the camera rolls as it does there).
glm::dvec3 perpendicularTo(glm::dvec3 n) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  return {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

// Mitsuba's camera frame: local +z looks from origin to target, +y is up, +x = up x dir (left).
glm::dmat4 lookAt(const XmlDocument& document, const XmlNode& node) {
  allowOnly(document, node, {"origin", "target", "up"});
  const glm::dvec3 origin = vectorAttribute(document, node, "origin");
  const glm::dvec3 target = vectorAttribute(document, node, "target");
  glm::dvec3 up = node.attribute("up") ? vectorAttribute(document, node, "up") : glm::dvec3(0.0);
  const glm::dvec3 dir = glm::normalize(target - origin);
  if (up == glm::dvec3(0.0)) up = perpendicularTo(dir);
  const glm::dvec3 left = glm::normalize(glm::cross(up, dir));
  const glm::dvec3 newUp = glm::cross(dir, left);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(left, 0.0);
  m[1] = glm::dvec4(newUp, 0.0);
  m[2] = glm::dvec4(dir, 0.0);
  m[3] = glm::dvec4(origin, 1.0);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]))
        document.fail(node, "degenerate lookat: target equals origin, or up is parallel to the view direction");
  return m;
}

glm::dmat4 matrix(const XmlDocument& document, const XmlNode& node) {
  allowOnly(document, node, {"value"});
  const std::vector<std::string> words = splitValueList(required(document, node, "value"));
  if (words.size() != 16 && words.size() != 9)
    document.fail(node, "a matrix holds 16 (4 x 4) or 9 (3 x 3) numbers, row by row; got " + std::to_string(words.size()));
  const size_t n = words.size() == 16 ? 4 : 3;
  glm::dmat4 m(1.0);
  for (size_t row = 0; row < n; ++row)
    for (size_t column = 0; column < n; ++column) {
      const std::optional<double> v = parseFiniteNumber(words[row * n + column]);
      if (!v) document.fail(node, "matrix: " + quote(words[row * n + column]) + " is not a finite number");
      m[column][row] = *v;
    }
  return m;
}

}  // namespace

std::string quote(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  out += text;
  out += '"';
  return out;
}

std::vector<std::string> splitValueList(std::string_view text) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text) {
    if (c == ' ' || c == ',' || c == '\t' || c == '\n' || c == '\r') {
      if (!word.empty()) words.push_back(std::move(word));
      word.clear();
    } else {
      word += c;
    }
  }
  if (!word.empty()) words.push_back(std::move(word));
  return words;
}

std::optional<double> parseFiniteNumber(std::string_view text) {
  const std::vector<std::string> words = splitValueList(text);
  if (words.size() != 1) return std::nullopt;
  const std::string& word = words.front();
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (end != word.c_str() + word.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

double numberAttribute(const XmlDocument& document, const XmlNode& node, std::string_view key) {
  const std::string& text = required(document, node, key);
  const std::optional<double> v = parseFiniteNumber(text);
  if (!v) document.fail(node, std::string(key) + ": " + quote(text) + " is not a finite number");
  return *v;
}

glm::dvec3 vectorAttribute(const XmlDocument& document, const XmlNode& node, std::string_view key) {
  const std::string& text = required(document, node, key);
  const std::vector<std::string> words = splitValueList(text);
  if (words.size() != 3) document.fail(node, std::string(key) + ": expected 3 numbers, got " + quote(text));
  glm::dvec3 v;
  for (int k = 0; k < 3; ++k) {
    const std::optional<double> number = parseFiniteNumber(words[size_t(k)]);
    if (!number) document.fail(node, std::string(key) + ": " + quote(words[size_t(k)]) + " is not a finite number");
    v[k] = *number;
  }
  return v;
}

glm::dmat4 parseTransform(const XmlDocument& document, const XmlNode& transform) {
  glm::dmat4 m(1.0);
  for (const XmlNode& op : transform.children) {
    glm::dmat4 step(1.0);
    if (op.tag == "translate") {
      allowOnly(document, op, {"x", "y", "z", "value"});
      step[3] = glm::dvec4(components(document, op, 0.0), 1.0);
    } else if (op.tag == "scale") {
      allowOnly(document, op, {"x", "y", "z", "value"});
      const glm::dvec3 s = components(document, op, 1.0);
      step[0][0] = s.x, step[1][1] = s.y, step[2][2] = s.z;
    } else if (op.tag == "rotate") {
      allowOnly(document, op, {"x", "y", "z", "value", "angle"});
      const glm::dvec3 axis = components(document, op, 0.0);
      if (axis == glm::dvec3(0.0)) document.fail(op, "the rotation axis is zero");
      step = rotation(axis, numberAttribute(document, op, "angle"));
    } else if (op.tag == "lookat") {
      step = lookAt(document, op);
    } else if (op.tag == "matrix") {
      step = matrix(document, op);
    } else {
      document.fail(op, "not a transform operation (a <transform> holds translate, rotate, scale, lookat and matrix)");
    }
    if (!op.children.empty()) document.fail(op.children.front(), "a transform operation holds no elements");
    m = step * m;
  }
  return m;
}

}  // namespace vktg
