#include "scene/scan.h"

#include <cmath>
#include <tuple>

#include "vktg/error.h"

namespace vktg {
namespace {

constexpr uint32_t kScanVersion = 1;

// The grid's point (i, j) of n x m: corner + across i / (n - 1) + down j / (m - 1).
glm::vec3 gridPoint(glm::vec3 corner, glm::vec3 across, glm::vec3 down, uint32_t i, uint32_t j, uint32_t n, uint32_t m) {
  glm::vec3 p = corner;
  if (n > 1) p += across * (float(i) / float(n - 1));
  if (m > 1) p += down * (float(j) / float(m - 1));
  return p;
}

Scan parseGrid(const JsonValue& value, const Scene& scene) {
  const JsonObject o(value, {"corner", "across", "down", "resolution", "normal", "look_at", "up", "lights"});
  o.field("resolution").numbers(2);  // two numbers; each an integer in range below
  Scan scan;
  scan.grid = true;
  for (size_t k = 0; k < 2; ++k) {
    const JsonValue r = o.field("resolution").element(k);
    (k == 0 ? scan.columns : scan.rows) = r.uinteger(1, kMaxScanViews);
  }
  if (uint64_t(scan.columns) * scan.rows > kMaxScanViews)
    o.field("resolution").fail(std::to_string(uint64_t(scan.columns) * scan.rows) + " points; a scan holds at most " +
                               std::to_string(kMaxScanViews));
  const glm::vec3 corner = o.field("corner").vec3();
  const glm::vec3 across = o.vec3("across", glm::vec3(0.0f)), down = o.vec3("down", glm::vec3(0.0f));
  for (auto [key, vector, count] : {std::tuple{"across", across, scan.columns}, std::tuple{"down", down, scan.rows}}) {
    if (count > 1 && !(glm::length(vector) > 0))
      (o.has(key) ? o.field(key) : JsonValue{&value.json(), value.file, o.pathOf(key)})
          .fail(std::string(key) + " must be a non-zero vector: the " + std::to_string(count) + " points along it would coincide");
  }
  // The pose fields every point shares, checked as a view's are.
  Json shared = Json::object();
  for (const char* key : {"normal", "look_at", "up"})
    if (o.has(key)) shared[key] = o.field(key).json();
  const SceneView base = parseSceneView(JsonValue{&shared, value.file, value.path}, scene);
  std::vector<uint32_t> following;  // point lights that sit at every scan point (a confocal scan)
  if (o.has("lights")) {
    const JsonValue names = o.field("lights");
    for (size_t k = 0; k < names.array().size(); ++k) {
      const JsonValue name = names.element(k);
      following.push_back(pointLightIndex(name, scene, name.string()));
    }
  }
  const bool perspective = scene.camera.type == CameraType::Perspective;
  for (uint32_t j = 0; j < scan.rows; ++j)
    for (uint32_t i = 0; i < scan.columns; ++i) {
      SceneView view = base;
      view.position = gridPoint(corner, across, down, i, j, scan.columns, scan.rows);
      const glm::vec3 p = *view.position;
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))  // finite fields whose sum overflows
        value.fail("grid point (" + std::to_string(i) + ", " + std::to_string(j) + ") is not a finite position");
      if (perspective) {
        const glm::vec3 direction = view.lookAt.value_or(scene.camera.lookAt) - *view.position;
        const glm::vec3 up = view.up.value_or(scene.camera.up);
        if (!(glm::length(direction) > 0) || glm::length(glm::cross(glm::normalize(direction), glm::normalize(up))) < 1e-6f)
          value.fail("degenerate view at grid point (" + std::to_string(i) + ", " + std::to_string(j) +
                     "): it looks at its own position or along up");
      }
      for (uint32_t light : following) view.lightPositions.emplace_back(light, *view.position);
      scan.views.push_back(std::move(view));
    }
  return scan;
}

Scan parseViews(const JsonValue& value, const Scene& scene) {
  const size_t count = value.array().size();
  if (count == 0) value.fail("a scan needs at least one view");
  if (count > kMaxScanViews) value.fail(std::to_string(count) + " views; a scan holds at most " + std::to_string(kMaxScanViews));
  Scan scan;
  for (size_t k = 0; k < count; ++k) scan.views.push_back(parseSceneView(value.element(k), scene));
  scan.columns = uint32_t(count);
  scan.rows = 1;
  return scan;
}

}  // namespace

Scan parseScanJson(const std::string& text, const std::string& file, const Scene& scene) {
  const Json json = parseJsonText(text, file);
  const JsonValue rootValue{&json, file, ""};
  const JsonObject root(rootValue, {"version", "description", "grid", "views"});
  const JsonValue version = root.field("version");
  const uint32_t v = version.uinteger(0, ~0u);
  if (v != kScanVersion)
    version.fail("unsupported version " + std::to_string(v) + " (this vktg reads version " + std::to_string(kScanVersion) + ")");
  if (root.has("description")) root.field("description").string();
  if (root.has("grid") == root.has("views")) rootValue.fail("a scan is either a \"grid\" or a list of \"views\", one of the two");
  return root.has("grid") ? parseGrid(root.field("grid"), scene) : parseViews(root.field("views"), scene);
}

Scan loadScan(const std::filesystem::path& path, const Scene& scene) {
  return parseScanJson(readTextFile(path), path.string(), scene);
}

}  // namespace vktg
