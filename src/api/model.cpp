// vktg::Model: a scene and the values of its parameters.
#include <cmath>

#include "vktg/vktg.h"

namespace vktg {

Model::Model(Scene scene) : m_scene(std::move(scene)), m_theta(m_scene.parameters.size(), 0.0) {}

Model Model::load(const std::filesystem::path& file) { return Model(loadScene(file)); }
Model Model::parse(const std::string& json, const std::string& name, const std::filesystem::path& baseDir) {
  return Model(parseSceneJson(json, name, baseDir));
}
Model Model::builtIn() { return Model(defaultScene()); }

std::vector<std::string> Model::parameterNames() const {
  std::vector<std::string> names;
  for (const Parameter& p : m_scene.parameters) names.push_back(p.name);
  return names;
}

std::vector<std::string> Model::select(const std::string& list) const { return selectParameters(m_scene, list); }

double Model::value(const std::string& name) const {
  // The scene may have gained parameters since (scene() is writable): those are at 0.
  const uint32_t k = findParameter(m_scene, name, "parameter");
  return k < m_theta.size() ? m_theta[k] : 0.0;
}

void Model::setValue(const std::string& name, double theta) {
  const uint32_t k = findParameter(m_scene, name, "parameter");
  if (!std::isfinite(theta)) throw Error("parameter: " + name + ": the value is not finite");
  m_theta.resize(m_scene.parameters.size(), 0.0);
  m_theta[k] = theta;
}

std::vector<double> Model::values(const std::vector<std::string>& names) const {
  std::vector<double> out;
  for (const std::string& name : names) out.push_back(value(name));
  return out;
}

void Model::setValues(const std::vector<std::string>& names, const std::vector<double>& theta) {
  if (names.size() != theta.size())
    throw Error("parameter: " + std::to_string(theta.size()) + " values for " + std::to_string(names.size()) + " names");
  for (size_t k = 0; k < names.size(); ++k)
    if (!std::isfinite(theta[k])) throw Error("parameter: " + names[k] + ": the value is not finite");
  for (size_t k = 0; k < names.size(); ++k) setValue(names[k], theta[k]);
}

Scene Model::current() const {
  std::vector<std::pair<uint32_t, double>> moved;
  for (uint32_t k = 0; k < m_theta.size() && k < m_scene.parameters.size(); ++k)
    if (m_theta[k] != 0.0) moved.push_back({k, m_theta[k]});
  return moved.empty() ? m_scene : applyParameters(m_scene, moved);
}

}  // namespace vktg
