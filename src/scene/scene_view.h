// A view of a scene: where its camera or point sensor stands and which point lights sit elsewhere
// than the scene puts them. The targets of an experiment (docs/optimize.md) and the points of a scan
// (docs/scene-format.md, "Scans") are views of one scene that one render can hold together.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene_values.h"
#include "vktg/scene.h"

namespace vktg {

struct SceneView {
  std::optional<glm::vec3> position;  // camera eye or sensor position
  std::optional<glm::vec3> lookAt;    // perspective only
  std::optional<glm::vec3> up;        // perspective only (unit length once parsed)
  std::optional<glm::vec3> normal;    // point sensor only (unit length once parsed)
  std::vector<std::pair<uint32_t, glm::vec3>> lightPositions;  // Scene::pointLights index -> position
  // Optical path outside the scene, in metres, added to every path of this view before the gate
  // sees it: the legs from a capture device to the relay wall and back, when a capture's times
  // count them (docs/scene-format.md, "NLOS captures"). 0 for a camera or sensor in the scene.
  float pathOffset = 0.0f;
};

// {"position", "look_at", "up", "normal", "lights": {"NAME": [x, y, z]}}, the fields that fit the
// scene's camera; every error names the field: a field for the other camera type, a degenerate pose
// (look_at at the position, up zero or along the view direction, a zero normal), an unknown light.
SceneView parseSceneView(const JsonValue& value, const Scene& scene);

// The index in scene.pointLights of the light called `name`; an unknown name fails at `where`,
// listing the scene's point lights.
uint32_t pointLightIndex(const JsonValue& where, const Scene& scene, const std::string& name);

// `camera` moved as `view` says (its type, image size and field of view stay).
Camera cameraSeenFrom(const Camera& camera, const SceneView& view);

}  // namespace vktg
