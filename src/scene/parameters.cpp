// Scene parameters: validation, finite-difference perturbation, velocity fields and command-line
// selection. perturbScene and bindParameters describe the same motion, one as a displaced scene and
// one as its derivative at θ = 0; tests/unit_parameters.cpp checks that they agree.
#include "vktg/parameters.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "vktg/error.h"
#include "vktg/scene.h"

namespace vktg {
namespace {

constexpr double kMinRoughness = 1e-3;   // the scene format's lower bound; the BSDFs clamp below it
constexpr double kUnitTolerance = 1e-5;  // how far |axis| may be from 1 after rounding to float

template <typename T>
int indexByName(const std::vector<T>& items, const std::string& name) {
  for (size_t i = 0; i < items.size(); ++i)
    if (items[i].name == name) return int(i);
  return -1;
}

// Rodrigues' formula: `point` turned by `angle` radians about the unit `axis` through `center`.
glm::dvec3 rotateAbout(const glm::dvec3& point, const glm::dvec3& axis, const glm::dvec3& center, double angle) {
  const glm::dvec3 r = point - center;
  const double c = std::cos(angle), s = std::sin(angle);
  return center + r * c + glm::cross(axis, r) * s + axis * (glm::dot(axis, r) * (1.0 - c));
}

std::string axisProblem(const glm::vec3& axis, const char* what) {
  const double length = glm::length(glm::dvec3(axis));
  if (!std::isfinite(length)) return std::string(what) + " is not finite";
  if (length == 0) return std::string("zero ") + what + ": it must give a direction";
  if (std::abs(length - 1.0) > kUnitTolerance) return std::string(what) + " must be a unit vector";
  return "";
}

bool materialInUse(const Scene& scene, int material) {
  for (const Shape& shape : scene.shapes)
    if (int(shape.material) == material) return true;
  return false;
}

// Edit distance, for suggesting names close to a mistyped one.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

std::string formatValue(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Adds `delta` to a scalar, failing when the result leaves [lo, hi] (open at an end if `open`).
float shifted(float value, double delta, double lo, double hi, bool openLow, const std::string& file,
              const std::string& name, const char* what) {
  const double moved = double(value) + delta;
  const bool below = openLow ? !(moved > lo) : !(moved >= lo);
  if (below || moved > hi) {
    std::string range(openLow ? "(" : "[");
    range += formatValue(lo) + ", " + (std::isinf(hi) ? std::string("inf)") : formatValue(hi) + "]");
    fail(file, name,
         std::string(what) + " " + formatValue(value) + " moved by " + formatValue(delta) + " is " +
             formatValue(moved) + ", outside " + range + ": use a smaller step");
  }
  return float(moved);
}

}  // namespace

bool isValidParameterName(const std::string& name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
  });
}

VertexExpansion vertexExpansion(const std::string& type, const std::string& shape) {
  if (type == "heightfield_heights") return {{""}, shape + "_h"};
  if (type == "vertex_positions") return {{"_x", "_y", "_z"}, shape + "_v"};
  return {};
}

bool isGeometric(ParameterKind kind) { return movesVertices(kind) || kind == ParameterKind::LightPosition; }

bool isGeometric(const Parameter& parameter) { return isGeometric(parameter.kind); }

bool movesVertices(ParameterKind kind) {
  return kind == ParameterKind::Translate || kind == ParameterKind::Rotate || kind == ParameterKind::Displace;
}

const char* parameterKindName(ParameterKind kind) {
  switch (kind) {
    case ParameterKind::Translate: return "translate";
    case ParameterKind::Rotate: return "rotate";
    case ParameterKind::Displace: return "displace";
    case ParameterKind::LightPosition: return "light_position";
    case ParameterKind::Emission: return "emission";
    case ParameterKind::Intensity: return "intensity";
    case ParameterKind::Albedo: return "albedo";
    case ParameterKind::Roughness: return "roughness";
    case ParameterKind::Ior: return "ior";
    case ParameterKind::GateCenter: return "gate_center";
  }
  return "unknown";
}

std::string parameterProblem(const Scene& scene, const Parameter& p) {
  if (!isValidParameterName(p.name))
    return "invalid parameter name \"" + p.name + "\" (use letters, digits, '_', '-' and '.')";
  switch (p.kind) {
    case ParameterKind::Translate:
    case ParameterKind::Rotate:
    case ParameterKind::Displace:
    case ParameterKind::Emission: {
      const int s = indexByName(scene.shapes, p.target);
      if (s < 0) return "unknown shape \"" + p.target + "\"";
      const Shape& shape = scene.shapes[size_t(s)];
      if (p.kind == ParameterKind::Emission)
        return shape.emission > 0 ? ""
                                  : "shape \"" + p.target +
                                        "\" does not emit (emission 0): it is no light the renderer samples, so "
                                        "its emission has no derivative; give it a small emission";
      if (p.kind == ParameterKind::Displace) {
        const double speed = glm::length(glm::dvec3(p.axis));
        if (!std::isfinite(speed)) return "direction is not finite";
        if (speed == 0) return "zero direction: the vertices would not move";
        if (p.vertices.empty()) return "no vertices to displace";
        std::set<uint32_t> seen;
        for (uint32_t v : p.vertices) {
          if (v >= shape.positions.size())
            return "vertex index " + std::to_string(v) + " out of range (shape \"" + p.target + "\" has " +
                   std::to_string(shape.positions.size()) + " vertices)";
          if (!seen.insert(v).second) return "vertex index " + std::to_string(v) + " given twice";
        }
        return "";
      }
      return axisProblem(p.axis, "axis");
    }
    case ParameterKind::LightPosition:
    case ParameterKind::Intensity: {
      const int l = indexByName(scene.pointLights, p.target);
      if (l < 0) return "unknown light \"" + p.target + "\"";
      if (p.kind == ParameterKind::LightPosition) return axisProblem(p.axis, "axis");
      return scene.pointLights[size_t(l)].intensity > 0
                 ? ""
                 : "light \"" + p.target + "\" is dark (intensity 0): the renderer never samples it, so its "
                                           "intensity has no derivative; give it a small intensity";
    }
    case ParameterKind::Albedo:
    case ParameterKind::Roughness:
    case ParameterKind::Ior: {
      const int m = indexByName(scene.materials, p.target);
      if (m < 0) return "unknown material \"" + p.target + "\"";
      if (!materialInUse(scene, m)) return "material \"" + p.target + "\" is used by no shape: its derivative is zero";
      const MaterialType type = scene.materials[size_t(m)].type;
      if (p.kind == ParameterKind::Albedo && type == MaterialType::Dielectric)
        return "material \"" + p.target + "\" is a dielectric, which has no albedo (it loses no energy)";
      if (p.kind == ParameterKind::Roughness && type == MaterialType::Diffuse)
        return "material \"" + p.target + "\" is diffuse, which has no roughness";
      if (p.kind == ParameterKind::Ior && type != MaterialType::Dielectric)
        return "material \"" + p.target + "\" is not a dielectric, so it has no index of refraction";
      return "";
    }
    case ParameterKind::GateCenter:
      return scene.gate.type == GateType::Steady ? "the gate is steady: shifting it changes nothing" : "";
  }
  return "unknown parameter kind";
}

std::string parameterSuggestions(const Scene& scene, const std::string& name) {
  if (scene.parameters.empty()) return " (the scene defines no parameters; see \"parameters\" in docs/scene-format.md)";
  constexpr size_t kMaxShown = 6;
  std::vector<std::pair<size_t, std::string>> close;
  const size_t allowed = std::max<size_t>(1, name.size() / 3);
  for (const Parameter& p : scene.parameters) {
    const size_t d = editDistance(name, p.name);
    const bool prefix = !name.empty() && (p.name.rfind(name, 0) == 0 || name.rfind(p.name, 0) == 0);
    if (d <= allowed || prefix) close.emplace_back(d, p.name);
  }
  std::stable_sort(close.begin(), close.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::string list;
  const bool guessed = !close.empty();
  if (!guessed)
    for (const Parameter& p : scene.parameters) close.emplace_back(0, p.name);
  for (size_t i = 0; i < close.size() && i < kMaxShown; ++i) list += (i ? ", " : "") + close[i].second;
  if (close.size() > kMaxShown) list += ", ... (" + std::to_string(close.size() - kMaxShown) + " more)";
  return (guessed ? " (did you mean: " : " (the scene defines: ") + list + ")";
}

bool matchesWildcard(const std::string& pattern, const std::string& text) {
  size_t p = 0, t = 0, star = std::string::npos, resume = 0;
  while (t < text.size()) {
    if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      resume = t;
    } else if (p < pattern.size() && pattern[p] == text[t]) {
      ++p;
      ++t;
    } else if (star != std::string::npos) {
      p = star + 1;
      t = ++resume;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

uint32_t findParameter(const Scene& scene, const std::string& name, const std::string& field) {
  for (size_t i = 0; i < scene.parameters.size(); ++i)
    if (scene.parameters[i].name == name) return uint32_t(i);
  fail(scene.source.string(), field, "unknown parameter \"" + name + "\"" + parameterSuggestions(scene, name));
}

glm::dvec3 moveVertex(const Parameter& p, const glm::dvec3& position, double theta) {
  if (p.kind == ParameterKind::Rotate) return rotateAbout(position, glm::dvec3(p.axis), glm::dvec3(p.center), theta);
  return position + glm::dvec3(p.axis) * theta;
}

glm::dvec3 turnVector(const Parameter& p, const glm::dvec3& vector, double theta) {
  if (p.kind != ParameterKind::Rotate) return vector;
  return rotateAbout(vector, glm::dvec3(p.axis), glm::dvec3(0.0), theta);
}

void applyParameter(Scene& out, const Parameter& p, double delta) {
  const std::string file = out.source.string();
  const std::string& name = p.name;
  if (!std::isfinite(delta)) fail(file, name, "perturbation " + formatValue(delta) + " is not finite");
  const std::string problem = parameterProblem(out, p);
  if (!problem.empty()) fail(file, name, problem);
  if (delta == 0) return;

  auto shapeOf = [&]() -> Shape& { return out.shapes[size_t(indexByName(out.shapes, p.target))]; };
  auto lightOf = [&]() -> PointLight& { return out.pointLights[size_t(indexByName(out.pointLights, p.target))]; };
  auto materialOf = [&]() -> Material& { return out.materials[size_t(indexByName(out.materials, p.target))]; };
  switch (p.kind) {
    case ParameterKind::Translate:
    case ParameterKind::Rotate:
      for (glm::vec3& v : shapeOf().positions) v = glm::vec3(moveVertex(p, glm::dvec3(v), delta));
      break;
    case ParameterKind::Displace: {
      std::vector<glm::vec3>& positions = shapeOf().positions;
      for (uint32_t i : p.vertices) positions[i] = glm::vec3(moveVertex(p, glm::dvec3(positions[i]), delta));
      break;
    }
    case ParameterKind::LightPosition: {
      PointLight& light = lightOf();
      light.position = glm::vec3(glm::dvec3(light.position) + glm::dvec3(p.axis) * delta);
      break;
    }
    case ParameterKind::Emission: {
      Shape& shape = shapeOf();
      shape.emission = shifted(shape.emission, delta, 0.0, INFINITY, true, file, name, "emission");
      break;
    }
    case ParameterKind::Intensity: {
      PointLight& light = lightOf();
      light.intensity = shifted(light.intensity, delta, 0.0, INFINITY, true, file, name, "intensity");
      break;
    }
    case ParameterKind::Albedo: {
      Material& m = materialOf();
      m.albedo = shifted(m.albedo, delta, 0.0, 1.0, false, file, name, "albedo");
      break;
    }
    case ParameterKind::Roughness: {
      Material& m = materialOf();
      m.roughness = shifted(m.roughness, delta, kMinRoughness, 1.0, false, file, name, "roughness");
      break;
    }
    case ParameterKind::Ior: {
      Material& m = materialOf();
      m.ior = shifted(m.ior, delta, 1.0, INFINITY, true, file, name, "ior");
      break;
    }
    case ParameterKind::GateCenter: {
      Gate& gate = out.gate;
      gate = gate.shifted(delta);  // a steady gate is rejected by parameterProblem
      try {
        validateGate(gate, file, name);
      } catch (const Error& e) {
        fail("", "", std::string(e.what()) + " (gate moved by " + formatValue(delta) + " m: use a smaller step)");
      }
      break;
    }
  }
}

Scene applyParameters(const Scene& scene, const std::vector<std::pair<uint32_t, double>>& values) {
  std::vector<std::pair<uint32_t, double>> ordered = values;
  std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Scene out = scene;
  for (const auto& [index, value] : ordered) {
    if (index >= scene.parameters.size()) throw Error("internal: parameter index out of range");
    applyParameter(out, scene.parameters[index], value);
  }
  return out;
}

Scene perturbScene(const Scene& scene, const std::string& name, double delta) {
  return applyParameters(scene, {{findParameter(scene, name, "parameter"), delta}});
}

ParameterRange parameterRange(const Scene& scene, const Parameter& p) {
  ParameterRange r;
  auto above = [&](double base, double lo) {
    r.low = lo - base;
    r.lowOpen = true;
  };
  auto between = [&](double base, double lo, double hi) {
    r.low = lo - base;
    r.high = hi - base;
  };
  switch (p.kind) {
    case ParameterKind::Translate:
    case ParameterKind::Rotate:
    case ParameterKind::Displace:
    case ParameterKind::LightPosition: break;
    case ParameterKind::Emission: above(scene.shapes[size_t(indexByName(scene.shapes, p.target))].emission, 0.0); break;
    case ParameterKind::Intensity:
      above(scene.pointLights[size_t(indexByName(scene.pointLights, p.target))].intensity, 0.0);
      break;
    case ParameterKind::Albedo: between(scene.materials[size_t(indexByName(scene.materials, p.target))].albedo, 0.0, 1.0); break;
    case ParameterKind::Roughness:
      between(scene.materials[size_t(indexByName(scene.materials, p.target))].roughness, kMinRoughness, 1.0);
      break;
    case ParameterKind::Ior: above(scene.materials[size_t(indexByName(scene.materials, p.target))].ior, 1.0); break;
    case ParameterKind::GateCenter: {
      const Gate& g = scene.gate;
      double lowest = 0;
      switch (g.type) {
        case GateType::Steady: return r;
        case GateType::Gaussian: lowest = g.mu; break;
        case GateType::TruncatedGaussian: lowest = std::min(g.mu, g.a); break;
        case GateType::Box: lowest = g.a; break;
        case GateType::Bins: lowest = g.binStart; break;
      }
      r.low = -lowest;
      break;
    }
  }
  return r;
}

std::vector<ParameterBinding> bindParameters(const Scene& scene, const std::vector<std::string>& names) {
  std::vector<uint32_t> firstVertex(scene.shapes.size() + 1, 0);
  for (size_t s = 0; s < scene.shapes.size(); ++s)
    firstVertex[s + 1] = firstVertex[s] + uint32_t(scene.shapes[s].positions.size());

  std::vector<ParameterBinding> bindings;
  for (const std::string& name : names) {
    const uint32_t index = findParameter(scene, name, "parameter");
    const Parameter& p = scene.parameters[index];
    const std::string problem = parameterProblem(scene, p);
    if (!problem.empty()) fail(scene.source.string(), name, problem);

    ParameterBinding b;
    b.name = p.name;
    b.kind = p.kind;
    b.parameter = index;
    switch (p.kind) {
      case ParameterKind::Translate:
      case ParameterKind::Rotate:
      case ParameterKind::Displace:
      case ParameterKind::Emission: b.target = uint32_t(indexByName(scene.shapes, p.target)); break;
      case ParameterKind::LightPosition:
      case ParameterKind::Intensity: b.target = uint32_t(indexByName(scene.pointLights, p.target)); break;
      case ParameterKind::Albedo:
      case ParameterKind::Roughness:
      case ParameterKind::Ior: b.target = uint32_t(indexByName(scene.materials, p.target)); break;
      case ParameterKind::GateCenter: b.target = 0; break;
    }
    if (movesVertices(p.kind)) {
      b.vertexVelocity.assign(firstVertex.back(), glm::vec3(0.0f));
      const Shape& shape = scene.shapes[b.target];
      glm::vec3* velocity = b.vertexVelocity.data() + firstVertex[b.target];
      if (p.kind == ParameterKind::Translate)
        std::fill(velocity, velocity + shape.positions.size(), p.axis);
      if (p.kind == ParameterKind::Rotate)
        for (size_t i = 0; i < shape.positions.size(); ++i)
          velocity[i] = glm::vec3(glm::cross(glm::dvec3(p.axis), glm::dvec3(shape.positions[i]) - glm::dvec3(p.center)));
      if (p.kind == ParameterKind::Displace)
        for (uint32_t i : p.vertices) velocity[i] = p.axis;
    }
    if (p.kind == ParameterKind::LightPosition) b.lightVelocity = p.axis;
    bindings.push_back(std::move(b));
  }
  return bindings;
}

std::vector<std::string> selectParameters(const Scene& scene, const std::string& list, const std::string& field) {
  const std::string file = scene.source.string();
  std::vector<std::string> selected;
  std::set<std::string> taken;
  auto take = [&](const std::string& name) {
    if (taken.insert(name).second) selected.push_back(name);
  };
  std::stringstream stream(list);
  std::string item;
  bool any = false;
  while (std::getline(stream, item, ',')) {
    any = true;
    const std::string name = trim(item);
    if (name.empty()) fail(file, field, "empty name in the list \"" + list + "\"");
    if (name.find('*') == std::string::npos) {
      take(scene.parameters[findParameter(scene, name, field)].name);
      continue;
    }
    bool matched = false;
    for (const Parameter& p : scene.parameters)
      if (matchesWildcard(name, p.name)) {
        take(p.name);
        matched = true;
      }
    if (!matched) fail(file, field, "\"" + name + "\" matches no parameter" + parameterSuggestions(scene, name.substr(0, name.find('*'))));
  }
  if (!any || (!list.empty() && list.back() == ','))
    fail(file, field, "no parameter named: expected a list like \"a,b\" or \"h*\"");
  return selected;
}

}  // namespace vktg
