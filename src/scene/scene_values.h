// Strict readers for JSON files (scenes, experiments). Every reader knows the file and the JSON path
// of the value it reads, so every error reads "file: shapes[2].material: problem" (vktg::fail).
// Objects are opened with the list of fields they allow: anything else is an error, so typos never
// pass.
#pragma once
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "vktg/gate.h"
#include "vktg/scene.h"

namespace vktg {

using Json = nlohmann::json;

// A JSON value together with where it came from.
struct JsonValue {
  const Json* value;
  std::string file;
  std::string path;  // e.g. "shapes[2].transform.scale"; empty for the document root

  const Json& json() const { return *value; }
  JsonValue element(size_t index) const;  // array element, path "path[index]"
  [[noreturn]] void fail(const std::string& problem) const;

  // Type-checked reads of this value.
  double number() const;                  // finite number
  double length() const;                  // metres: a number, or a string "12.5ns" (times c) / "3m"
  uint32_t uinteger(uint32_t lo, uint32_t hi) const;  // integer in [lo, hi]
  bool boolean() const;
  std::string string() const;
  glm::vec3 vec3() const;                 // [x, y, z] of finite numbers
  std::vector<double> numbers(size_t count) const;  // array of exactly `count` finite numbers
  const Json& array() const;              // checks the type; elements via element()
  // A string from `accepted`; anything else fails "unknown value ... (expected one of: ...)".
  std::string oneOf(std::initializer_list<std::string_view> accepted) const;
};

// A JSON object whose fields are restricted to a known set.
class JsonObject {
 public:
  // Fails if `value` is not an object or holds a field outside `allowed`.
  JsonObject(const JsonValue& value, const std::vector<std::string_view>& allowed);

  bool has(std::string_view key) const;
  JsonValue field(std::string_view key) const;  // fails "missing required field" if absent
  std::string pathOf(std::string_view key) const;
  const JsonValue& self() const { return m_self; }

  // Optional fields with a default.
  double number(std::string_view key, double fallback) const;
  double length(std::string_view key, double fallback) const;
  uint32_t uinteger(std::string_view key, uint32_t fallback, uint32_t lo, uint32_t hi) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string string(std::string_view key, const std::string& fallback) const;
  glm::vec3 vec3(std::string_view key, glm::vec3 fallback) const;

 private:
  JsonValue m_self;
};

// A file's extension in lower case: ".GLB" and ".glb" name the same format.
std::string lowerExtension(const std::filesystem::path& path);

// `scene` with the parameters of a JSON array in the scene format's form ("Parameters" in
// docs/scene-format.md) added after its own, bound to its shapes, lights and materials by name;
// errors name the array's file and path.
Scene withParameters(Scene scene, const JsonValue& parameters);

// Range checks that name the field on failure.
void requireInRange(const JsonValue& where, double value, double lo, double hi);  // lo <= v <= hi
void requireAbove(const JsonValue& where, double value, double lo);               // v > lo
void requireAtLeast(const JsonValue& where, double value, double lo);             // v >= lo

std::string formatNumber(double value);

// The whole of a text file; fails naming the file if it is missing, not a regular file or unreadable.
std::string readTextFile(const std::filesystem::path& path);

// Parses JSON text. Syntax errors name the line and column; a key given twice in one object is an
// error (the JSON library would silently keep the last one).
Json parseJsonText(const std::string& text, const std::string& file);

// The `type` field of an object, which must be one of `accepted`.
std::string typeOf(const JsonValue& value, std::initializer_list<std::string_view> accepted);

// A gate object ({"type": "box", "a": 1, "b": 2}, ...) or {"spec": "box:1,2"}, validated
// (docs/scene-format.md "Gate").
Gate parseGateValue(const JsonValue& value);

// "auto", "standard", "ellipsoidal" or "mis".
NeeMode readNeeMode(const JsonValue& value);

}  // namespace vktg
