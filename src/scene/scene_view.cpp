#include "scene/scene_view.h"

#include <algorithm>
#include <string>

namespace vktg {
namespace {

std::string inQuotes(const std::string& text) { return "\"" + text + "\""; }

// {"NAME": [x, y, z], ...}: point lights of `scene` by name.
std::vector<std::pair<uint32_t, glm::vec3>> parseLightPositions(const JsonValue& value, const Scene& scene) {
  if (!value.json().is_object())
    value.fail("wrong type: expected an object mapping point-light names to positions [x, y, z]");
  std::vector<std::pair<uint32_t, glm::vec3>> positions;
  for (const auto& item : value.json().items()) {
    const JsonValue entry{&item.value(), value.file, value.path + "." + item.key()};
    positions.emplace_back(pointLightIndex(entry, scene, item.key()), entry.vec3());
  }
  return positions;
}

}  // namespace

uint32_t pointLightIndex(const JsonValue& where, const Scene& scene, const std::string& name) {
  const std::vector<PointLight>& lights = scene.pointLights;
  const auto light = std::find_if(lights.begin(), lights.end(), [&](const PointLight& l) { return l.name == name; });
  if (light == lights.end()) {
    std::string known;
    for (const PointLight& l : lights) known += (known.empty() ? "" : ", ") + l.name;
    where.fail("unknown point light " + inQuotes(name) +
               (known.empty() ? " (the scene has no point lights)" : " (the scene's point lights: " + known + ")"));
  }
  return uint32_t(light - lights.begin());
}

// A view overrides the pose of the scene's camera (fields that fit its type) and moves point lights.
SceneView parseSceneView(const JsonValue& value, const Scene& scene) {
  const JsonObject o(value, {"position", "look_at", "up", "normal", "lights", "path_offset"});
  const Camera& camera = scene.camera;
  const bool perspective = camera.type == CameraType::Perspective;
  for (std::string_view key : {"look_at", "up"})
    if (o.has(key) && !perspective)
      o.field(key).fail(std::string(key) +
                        " applies to perspective cameras, but the scene's camera is a point sensor (its view "
                        "takes position and normal)");
  if (o.has("normal") && perspective)
    o.field("normal").fail(
        "normal applies to point sensors, but the scene's camera is perspective (its view takes position, look_at "
        "and up)");

  SceneView view;
  if (o.has("position")) view.position = o.field("position").vec3();
  if (o.has("look_at")) view.lookAt = o.field("look_at").vec3();
  if (o.has("up")) view.up = o.field("up").vec3();
  if (o.has("normal")) view.normal = o.field("normal").vec3();
  if (o.has("path_offset")) {
    const double offset = o.number("path_offset", 0.0);
    if (!(offset >= 0.0 && offset <= 1e6))
      o.field("path_offset").fail("must be a length in [0, 1e6] m (optical path outside the scene), got " +
                                  std::to_string(offset));
    view.pathOffset = float(offset);
  }
  if (perspective) {
    const glm::vec3 position = view.position.value_or(camera.position);
    const glm::vec3 direction = view.lookAt.value_or(camera.lookAt) - position;
    const glm::vec3 up = view.up.value_or(camera.up);
    const JsonValue moved = o.has("look_at") ? o.field("look_at") : o.has("position") ? o.field("position") : value;
    if (!(glm::length(direction) > 0)) moved.fail("degenerate view: look_at equals position");
    if (!(glm::length(up) > 0)) o.field("up").fail("degenerate view: up must not be zero");
    if (glm::length(glm::cross(glm::normalize(direction), glm::normalize(up))) < 1e-6f)
      (o.has("up") ? o.field("up") : moved).fail("degenerate view: up is parallel to the view direction");
    if (view.up) view.up = glm::normalize(*view.up);
  } else if (view.normal) {
    if (!(glm::length(*view.normal) > 0)) o.field("normal").fail("degenerate view: normal must not be zero");
    view.normal = glm::normalize(*view.normal);
  }
  if (o.has("lights")) view.lightPositions = parseLightPositions(o.field("lights"), scene);
  return view;
}

Camera cameraSeenFrom(const Camera& camera, const SceneView& view) {
  Camera out = camera;
  if (view.position) out.position = *view.position;
  if (view.lookAt) out.lookAt = *view.lookAt;
  if (view.up) out.up = glm::normalize(*view.up);
  if (view.normal) out.normal = glm::normalize(*view.normal);
  return out;
}

}  // namespace vktg
