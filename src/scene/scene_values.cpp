#include "scene/scene_values.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "vktg/error.h"

namespace vktg {
namespace {

std::string typeName(const Json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "null";
}

std::string joinPath(const std::string& base, std::string_view key) {
  return base.empty() ? std::string(key) : base + "." + std::string(key);
}

}  // namespace

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

JsonValue JsonValue::element(size_t index) const {
  return JsonValue{&(*value)[index], file, path + "[" + std::to_string(index) + "]"};
}

void JsonValue::fail(const std::string& problem) const { vktg::fail(file, path, problem); }

double JsonValue::number() const {
  if (!value->is_number()) fail("wrong type: expected a number, got " + typeName(*value));
  double v = value->get<double>();
  if (!std::isfinite(v)) fail("must be finite, got " + formatNumber(v));
  // Scene values end up as 32-bit floats on the GPU; larger ones would become infinities there.
  if (std::abs(v) > std::numeric_limits<float>::max())
    fail("out of range: " + formatNumber(v) + " is not a finite 32-bit float");
  return v;
}

double JsonValue::length() const {
  if (value->is_number()) return number();
  if (!value->is_string()) fail("wrong type: expected a number or a string like \"12.5ns\", got " + typeName(*value));
  const std::string text = value->get<std::string>();
  double v = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  auto [rest, ec] = std::from_chars(begin, end, v);
  const std::string suffix(rest, end);
  if (ec != std::errc() || rest == begin || (suffix != "ns" && suffix != "m" && !suffix.empty()))
    fail("cannot read \"" + text + "\" as a length: expected a number with an optional \"ns\" or \"m\" suffix");
  if (suffix == "ns") v *= kSpeedOfLight;
  if (!std::isfinite(v)) fail("must be finite, got \"" + text + "\"");
  return v;
}

uint32_t JsonValue::uinteger(uint32_t lo, uint32_t hi) const {
  if (!value->is_number()) fail("wrong type: expected an integer, got " + typeName(*value));
  const double v = value->get<double>();
  if (!std::isfinite(v) || v != std::floor(v)) fail("must be an integer, got " + formatNumber(v));
  if (v < lo || v > hi)
    fail("out of range: " + formatNumber(v) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<uint32_t>(v);
}

bool JsonValue::boolean() const {
  if (!value->is_boolean()) fail("wrong type: expected a boolean, got " + typeName(*value));
  return value->get<bool>();
}

std::string JsonValue::string() const {
  if (!value->is_string()) fail("wrong type: expected a string, got " + typeName(*value));
  return value->get<std::string>();
}

std::vector<double> JsonValue::numbers(size_t count) const {
  if (!value->is_array()) fail("wrong type: expected an array of " + std::to_string(count) + " numbers, got " + typeName(*value));
  if (value->size() != count)
    fail("wrong length: expected " + std::to_string(count) + " numbers, got " + std::to_string(value->size()));
  std::vector<double> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = element(i).number();
  return out;
}

glm::vec3 JsonValue::vec3() const {
  const std::vector<double> v = numbers(3);
  return glm::vec3(float(v[0]), float(v[1]), float(v[2]));
}

const Json& JsonValue::array() const {
  if (!value->is_array()) fail("wrong type: expected an array, got " + typeName(*value));
  return *value;
}

std::string JsonValue::oneOf(std::initializer_list<std::string_view> accepted) const {
  const std::string text = string();
  std::string list;
  for (std::string_view a : accepted) {
    if (a == text) return text;
    list += (list.empty() ? "" : ", ") + std::string(a);
  }
  fail("unknown value \"" + text + "\" (expected one of: " + list + ")");
}

JsonObject::JsonObject(const JsonValue& value, const std::vector<std::string_view>& allowed) : m_self(value) {
  if (!value.json().is_object()) value.fail("wrong type: expected an object, got " + typeName(value.json()));
  for (const auto& item : value.json().items()) {
    bool known = false;
    for (std::string_view key : allowed) known = known || key == item.key();
    if (known) continue;
    std::string list;
    for (std::string_view key : allowed) list += (list.empty() ? "" : ", ") + std::string(key);
    vktg::fail(value.file, joinPath(value.path, item.key()),
               "unknown field (allowed here: " + (list.empty() ? std::string("none") : list) + ")");
  }
}

bool JsonObject::has(std::string_view key) const { return m_self.json().contains(key); }

std::string JsonObject::pathOf(std::string_view key) const { return joinPath(m_self.path, key); }

JsonValue JsonObject::field(std::string_view key) const {
  if (!has(key)) vktg::fail(m_self.file, pathOf(key), "missing required field");
  return JsonValue{&m_self.json()[std::string(key)], m_self.file, pathOf(key)};
}

double JsonObject::number(std::string_view key, double fallback) const {
  return has(key) ? field(key).number() : fallback;
}

double JsonObject::length(std::string_view key, double fallback) const {
  return has(key) ? field(key).length() : fallback;
}

uint32_t JsonObject::uinteger(std::string_view key, uint32_t fallback, uint32_t lo, uint32_t hi) const {
  return has(key) ? field(key).uinteger(lo, hi) : fallback;
}

bool JsonObject::boolean(std::string_view key, bool fallback) const {
  return has(key) ? field(key).boolean() : fallback;
}

std::string JsonObject::string(std::string_view key, const std::string& fallback) const {
  return has(key) ? field(key).string() : fallback;
}

glm::vec3 JsonObject::vec3(std::string_view key, glm::vec3 fallback) const {
  return has(key) ? field(key).vec3() : fallback;
}

void requireInRange(const JsonValue& where, double value, double lo, double hi) {
  if (value < lo || value > hi)
    where.fail("out of range: " + formatNumber(value) + " is not in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
}

void requireAbove(const JsonValue& where, double value, double lo) {
  if (!(value > lo)) where.fail("out of range: must be > " + formatNumber(lo) + ", got " + formatNumber(value));
}

void requireAtLeast(const JsonValue& where, double value, double lo) {
  if (!(value >= lo)) where.fail("out of range: must be >= " + formatNumber(lo) + ", got " + formatNumber(value));
}

std::string readTextFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) vktg::fail(path.string(), "", "file not found");
  if (!std::filesystem::is_regular_file(path, ec)) vktg::fail(path.string(), "", "cannot read: not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) vktg::fail(path.string(), "", "cannot read file (permission denied or I/O error)");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) vktg::fail(path.string(), "", "cannot read file (I/O error)");
  return text.str();
}

Json parseJsonText(const std::string& text, const std::string& file) {
  std::vector<std::set<std::string>> keysPerObject;
  std::string duplicate;
  auto callback = [&](int, Json::parse_event_t event, Json& parsed) {
    if (event == Json::parse_event_t::object_start) keysPerObject.emplace_back();
    if (event == Json::parse_event_t::object_end) keysPerObject.pop_back();
    if (event == Json::parse_event_t::key && !keysPerObject.back().insert(parsed.get<std::string>()).second &&
        duplicate.empty())
      duplicate = parsed.get<std::string>();
    return true;
  };
  Json json;
  try {
    json = Json::parse(text, callback);
  } catch (const Json::parse_error& e) {
    // nlohmann's message reads "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string message = e.what();
    const size_t at = message.find("parse error ");
    if (at != std::string::npos) message = message.substr(at + 12);
    vktg::fail(file, "", "malformed JSON (syntax error) " + message);
  } catch (const Json::exception& e) {
    // Other parser failures, e.g. "number overflow parsing '1e999'"; drop the "[json.exception...] " tag.
    std::string message = e.what();
    const size_t tag = message.find("] ");
    vktg::fail(file, "", "malformed JSON: " + (tag == std::string::npos ? message : message.substr(tag + 2)));
  }
  if (!duplicate.empty()) vktg::fail(file, duplicate, "duplicate field (given more than once in one object)");
  return json;
}

std::string typeOf(const JsonValue& value, std::initializer_list<std::string_view> accepted) {
  if (!value.json().is_object()) value.fail("wrong type: expected an object");
  if (!value.json().contains("type")) vktg::fail(value.file, value.path + ".type", "missing required field");
  const JsonValue type{&value.json()["type"], value.file, value.path + ".type"};
  const std::string name = type.string();
  std::string list;
  for (std::string_view a : accepted) {
    if (a == name) return name;
    list += (list.empty() ? "" : ", ") + std::string(a);
  }
  type.fail("unknown type \"" + name + "\" (expected one of: " + list + ")");
}

Gate parseGateValue(const JsonValue& value) {
  Gate gate;
  if (value.json().is_object() && value.json().contains("spec")) {
    const JsonObject o(value, {"spec"});
    try {
      gate = parseGateSpec(o.field("spec").string(), o.pathOf("spec"));
    } catch (const Error& e) {
      vktg::fail(value.file, "", e.what());
    }
  } else {
    const std::string type = typeOf(value, {"steady", "box", "gaussian", "truncated_gaussian", "bins"});
    if (type == "steady") {
      const JsonObject o(value, {"type"});
      gate.type = GateType::Steady;
    } else if (type == "box") {
      const JsonObject o(value, {"type", "a", "b"});
      gate.type = GateType::Box;
      gate.a = o.field("a").length();
      gate.b = o.field("b").length();
    } else if (type == "gaussian") {
      const JsonObject o(value, {"type", "mu", "sigma", "normalize"});
      gate.type = GateType::Gaussian;
      gate.mu = o.field("mu").length();
      gate.sigma = o.field("sigma").length();
      gate.normalize = o.boolean("normalize", false);
    } else if (type == "truncated_gaussian") {
      const JsonObject o(value, {"type", "mu", "sigma", "a", "b"});
      gate.type = GateType::TruncatedGaussian;
      gate.mu = o.field("mu").length();
      gate.sigma = o.field("sigma").length();
      gate.a = o.field("a").length();
      gate.b = o.field("b").length();
    } else {
      const JsonObject o(value, {"type", "start", "width", "count"});
      gate.type = GateType::Bins;
      gate.binStart = o.field("start").length();
      gate.binWidth = o.field("width").length();
      gate.binCount = o.field("count").uinteger(1, 65536);
    }
  }
  validateGate(gate, value.file, value.path);
  return gate;
}

NeeMode readNeeMode(const JsonValue& value) {
  const std::string mode = value.oneOf({"auto", "standard", "ellipsoidal", "mis"});
  if (mode == "standard") return NeeMode::Standard;
  if (mode == "ellipsoidal") return NeeMode::Ellipsoidal;
  if (mode == "mis") return NeeMode::Mis;
  return NeeMode::Auto;
}

}  // namespace vktg
