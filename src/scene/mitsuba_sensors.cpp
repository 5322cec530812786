#include "scene/mitsuba_sensors.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>

#include "scene/mitsuba_values.h"
#include "scene/primitives.h"
#include "scene/scene_values.h"

namespace vktg {
namespace {

constexpr uint32_t kMaxFilmSide = 16384;  // the JSON camera's resolution limit
constexpr int64_t kMaxBins = 65536;        // the bins gate's count limit
constexpr double kDegrees = 180.0 / std::numbers::pi;
constexpr double kMaxPathOffset = 1e6;     // a view's path_offset in a scan file is at most this too

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

uint32_t integerIn(PluginElement& e, std::string_view name, int64_t fallback, int64_t lo, int64_t hi) {
  const std::optional<int64_t> v = e.integer(name);
  if (v && (*v < lo || *v > hi))
    e.document().fail(e.propertyNode(name), std::string(name) + " = " + std::to_string(*v) + " is not in [" +
                                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return uint32_t(v.value_or(fallback));
}

// A property that only one value keeps faithful to what Mitsuba renders.
template <class T>
void requireValue(PluginElement& e, std::string_view name, std::optional<T> value, T expected, const std::string& why) {
  if (value && *value != expected) e.document().fail(e.propertyNode(name), why);
}

// Mitsuba's reconstruction filters; vktg's pixel filter is a box (the filter only blurs the image).
void readPixelFilter(const XmlDocument& document, const XmlNode& node, bool transient) {
  PluginElement e(document, node);
  if (e.type() == "box") {
  } else if (transient) {
    e.fail("a transient_hdr_film bins samples with a box filter only (mitransient refuses other filters)");
  } else if (e.type() == "gaussian") {
    e.number("stddev");
  } else if (e.type() == "tent") {
    e.number("radius");
  } else if (e.type() == "mitchell") {
    e.number("B");
    e.number("C");
  } else if (e.type() == "lanczos") {
    e.integer("lobes");
  } else if (e.type() != "catmullrom") {
    e.fail("unknown reconstruction filter (Mitsuba's are box, tent, gaussian, mitchell, catmullrom, lanczos)");
  }
  e.finish();
}

// Mitsuba's field of view (sensor.cpp's parse_fov): fov along fov_axis, or a 35 mm focal length
// along the diagonal, as the horizontal field of view in degrees for a film of this aspect.
double horizontalFov(PluginElement& e, double aspect) {
  if (e.has("fov") && e.has("focal_length")) e.fail("give fov or focal_length, not both");
  double fov = 0;
  std::string axis;
  if (e.has("fov")) {
    fov = *e.number("fov");
    if (!(fov > 0 && fov < 180)) e.document().fail(e.propertyNode("fov"), "fov must lie in (0, 180) degrees");
    axis = lower(e.string("fov_axis").value_or("x"));
    if (axis == "smaller") axis = aspect > 1 ? "y" : "x";
    if (axis == "larger") axis = aspect > 1 ? "x" : "y";
    if (axis != "x" && axis != "y" && axis != "diagonal")
      e.document().fail(e.propertyNode("fov_axis"), "fov_axis must be x, y, diagonal, smaller or larger");
  } else {
    std::string text = e.string("focal_length").value_or("50mm");
    const std::string written = text;
    if (text.size() > 2 && text.substr(text.size() - 2) == "mm") text.resize(text.size() - 2);
    const std::optional<double> focal = parseFiniteNumber(text);
    if (!focal || !(*focal > 0))
      e.document().fail(e.propertyNode("focal_length"), "focal_length " + quote(written) + " is not a positive length in mm");
    fov = 2.0 * kDegrees * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * *focal));
    axis = "diagonal";
  }
  const double half = 0.5 * fov / kDegrees;
  double x = fov;
  if (axis == "y") x = 2.0 * kDegrees * std::atan(std::tan(half) * aspect);
  if (axis == "diagonal") x = 2.0 * kDegrees * std::atan(std::tan(half) / std::sqrt(1.0 + 1.0 / (aspect * aspect)));
  if (!(x > 0 && x < 180)) e.fail("the horizontal field of view must lie in (0, 180) degrees");
  return x;
}

glm::dvec3 applyPoint(const glm::dmat4& m, glm::dvec3 p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

// The laser of an NLOS capture: Mitsuba's projector puts power P = pi E scale A through its frustum
// (A: the image rectangle at unit distance, 4 tan^2(fov/2) for its square 1 x 1 texture). On a
// diffuse wall of albedo rho the spot radiates rho P cos / pi; the wall point a sensor looks at
// returns rho / pi of the irradiance vktg's point sensor measures. A point light of intensity
// rho^2 P / pi^2 at the spot gives mitransient's values wherever the spot's cosine is 1
// (docs/scene-format.md, "NLOS captures from mitransient").
double laserIntensity(const XmlDocument& document, const XmlNode& node, double albedo) {
  PluginElement p(document, node);
  if (p.type() != "projector")
    p.fail("the laser of an nlos_capture_meter is a projector emitter (mitransient's laser)");
  if (p.has("to_world"))
    p.document().fail(p.propertyNode("to_world"),
                      "the nlos_capture_meter aims its laser (laser_origin, laser_lookat_pixel or laser_lookat_3d); "
                      "a to_world on the projector would be overridden");
  const std::optional<XmlColor> irradiance = p.color("irradiance");
  double e = 1.0;
  if (irradiance) {
    for (double c : irradiance->channels)
      if (!(c >= 0)) document.fail(*irradiance->node, "irradiance must not be negative");
    e = irradiance->mean();
  }
  const double scale = p.number("scale").value_or(1.0);
  if (!(scale >= 0)) p.document().fail(p.propertyNode("scale"), "scale must not be negative");
  p.number("sampling_weight");
  const double halfFov = 0.5 * horizontalFov(p, 1.0) / kDegrees;
  p.finish();
  const double power = std::numbers::pi * e * scale * 4.0 * std::tan(halfFov) * std::tan(halfFov);
  const double intensity = albedo * albedo * power / (std::numbers::pi * std::numbers::pi);
  if (!(intensity <= double(std::numeric_limits<float>::max()))) p.fail("the laser's intensity is past the float range");
  return intensity;
}

}  // namespace

FilmSettings readFilm(const XmlDocument& document, const XmlNode* node) {
  FilmSettings film;
  if (!node) return film;
  film.node = node;
  PluginElement e(document, *node);
  film.transient = e.type() == "transient_hdr_film";
  if (e.type() != "hdrfilm" && !film.transient)
    e.fail("unsupported film (vktg reads hdrfilm and mitransient's transient_hdr_film)");
  film.width = integerIn(e, "width", 768, 1, kMaxFilmSide);
  film.height = integerIn(e, "height", 576, 1, kMaxFilmSide);
  const std::string crop = "vktg renders the whole film: a crop would change the image";
  requireValue<int64_t>(e, "crop_offset_x", e.integer("crop_offset_x"), 0, crop);
  requireValue<int64_t>(e, "crop_offset_y", e.integer("crop_offset_y"), 0, crop);
  requireValue<int64_t>(e, "crop_width", e.integer("crop_width"), film.width, crop);
  requireValue<int64_t>(e, "crop_height", e.integer("crop_height"), film.height, crop);
  requireValue(e, "sample_border", e.boolean("sample_border"), false, "sample_border is not supported");
  const std::vector<const XmlNode*> filters = e.objects("rfilter");
  if (filters.size() > 1) document.fail(*filters[1], "a film takes one reconstruction filter");
  for (const XmlNode* filter : filters) readPixelFilter(document, *filter, film.transient);
  if (!film.transient) {
    // How the image is stored: vktg writes single-channel float EXR whatever they say.
    e.string("file_format");
    e.string("pixel_format");
    e.string("component_format");
    e.boolean("compensate");
    e.boolean("banner");
  } else {
    const uint32_t bins = integerIn(e, "temporal_bins", 2048, 1, kMaxBins);
    const double width = e.number("bin_width_opl").value_or(0.003);
    if (!(width > 0)) document.fail(e.propertyNode("bin_width_opl"), "bin_width_opl must be positive");
    const double start = e.number("start_opl").value_or(0.0);
    if (!(start >= 0)) document.fail(e.propertyNode("start_opl"), "start_opl must not be negative");
    requireValue(e, "exhaustive_scan", e.boolean("exhaustive_scan"), false,
                 "exhaustive scans (every laser point for every sensor point) are not supported");
    e.number("laser_scan_width");  // used by exhaustive scans only
    e.number("laser_scan_height");
    // One bin is a box gate: the same image, a single layer.
    if (bins == 1) {
      film.gate.type = GateType::Box;
      film.gate.a = start;
      film.gate.b = start + width;
    } else {
      film.gate.type = GateType::Bins;
      film.gate.binStart = start;
      film.gate.binWidth = width;
      film.gate.binCount = bins;
    }
    validateGate(film.gate, document.location(*node), XmlDocument::describe(*node));
  }
  e.finish();
  return film;
}

SamplerSettings readSampler(const XmlDocument& document, const XmlNode* node) {
  SamplerSettings sampler;
  if (!node) return sampler;
  PluginElement e(document, *node);
  const std::string& type = e.type();
  if (type != "independent" && type != "stratified" && type != "multijitter" && type != "orthogonal" && type != "ldsampler")
    e.fail("unknown sampler (Mitsuba's are independent, stratified, multijitter, orthogonal, ldsampler)");
  sampler.spp = integerIn(e, "sample_count", 4, 1, int64_t(1) << 30);
  sampler.seed = integerIn(e, "seed", 0, 0, std::numeric_limits<uint32_t>::max());
  // How samples are placed changes the noise, not the image vktg converges to.
  if (type == "stratified" || type == "multijitter" || type == "orthogonal") e.boolean("jitter");
  if (type == "orthogonal") e.integer("strength");
  e.finish();
  return sampler;
}

Camera readPerspectiveCamera(PluginElement& e, const FilmSettings& film) {
  Camera camera;
  camera.type = CameraType::Perspective;
  camera.width = film.width;
  camera.height = film.height;
  const double aspect = double(film.width) / double(film.height);
  const double xFov = horizontalFov(e, aspect);
  camera.fovY = float(2.0 * kDegrees * std::atan(std::tan(0.5 * xFov / kDegrees) / aspect));
  if (!(camera.fovY > 0 && camera.fovY < 180))
    e.fail("the vertical field of view of this film's aspect is not in (0, 180) degrees");
  // Clipping planes only cut what the camera sees nearer than near_clip or farther than far_clip;
  // vktg has none (the docs say so). Mitsuba's own checks still apply.
  const double nearClip = e.number("near_clip").value_or(1e-2), farClip = e.number("far_clip").value_or(1e4);
  if (!(nearClip > 0)) e.fail("near_clip must be positive");
  if (!(nearClip < farClip)) e.fail("near_clip must be smaller than far_clip");
  e.number("focus_distance");  // a pinhole is in focus everywhere
  e.number("shutter_open");    // nothing moves during the exposure
  e.number("shutter_close");
  for (const char* key : {"principal_point_offset_x", "principal_point_offset_y"})
    requireValue(e, key, e.number(key), 0.0, "an off-centre principal point is not supported");
  const glm::dmat4 m = e.transform("to_world").value_or(glm::dmat4(1.0));
  const glm::dmat3 linear(m);
  const glm::dmat3 gram = linear * glm::transpose(linear);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(gram[i][j] - (i == j ? 1.0 : 0.0)) > 1e-3)
        e.document().fail(e.propertyNode("to_world"), "a sensor's to_world must not scale (Mitsuba refuses it too)");
  if (glm::determinant(linear) < 0)
    e.document().fail(e.propertyNode("to_world"), "a mirroring to_world would flip the image, which vktg's camera cannot");
  const glm::dvec3 position = applyPoint(m, glm::dvec3(0.0));
  const glm::dvec3 forward = glm::normalize(glm::dvec3(m * glm::dvec4(0, 0, 1, 0)));
  camera.position = glm::vec3(position);
  camera.lookAt = glm::vec3(position + forward);
  camera.up = glm::vec3(glm::normalize(glm::dvec3(m * glm::dvec4(0, 1, 0, 0))));
  if (!allFinite({camera.position, camera.lookAt, camera.up}) || camera.lookAt == camera.position)
    e.fail("the camera's position is too far from the origin for float precision");
  return camera;
}

NlosCapture readNlosCaptureMeter(PluginElement& meter, const RelayWall& wall, const XmlNode* sceneProjector,
                                 std::optional<bool> integratorAccounts, uint32_t laserIndex) {
  const XmlDocument& document = meter.document();
  NlosCapture capture;
  for (const char* key : {"original_film_width", "original_film_height"})
    if (meter.has(key))
      document.fail(meter.propertyNode(key), "mitransient's one-point confocal renders (original_film_*) are not supported: "
                                             "confocal=true renders the film's whole grid");
  const std::vector<const XmlNode*> films = meter.objects("film");
  if (films.size() > 1) document.fail(*films[1], "a sensor takes one film");
  capture.film = readFilm(document, films.empty() ? nullptr : films.front());
  const std::vector<const XmlNode*> samplers = meter.objects("sampler");
  if (samplers.size() > 1) document.fail(*samplers[1], "a sensor takes one sampler");
  capture.sampler = readSampler(document, samplers.empty() ? nullptr : samplers.front());
  const uint32_t columns = capture.film.width, rows = capture.film.height;
  if (uint64_t(columns) * rows > kMaxScanViews)
    document.fail(capture.film.node ? *capture.film.node : meter.node(),
                  "the capture grid has " + std::to_string(uint64_t(columns) * rows) + " points; vktg scans at most " +
                      std::to_string(kMaxScanViews));

  capture.confocal = meter.boolean("confocal").value_or(false);
  const glm::dvec3 sensorOrigin = meter.point("sensor_origin").value_or(glm::dvec3(0.0));
  const glm::dvec3 laserOrigin = meter.point("laser_origin").value_or(glm::dvec3(0.0));
  const std::optional<glm::dvec3> lookAtPixel = meter.point("laser_lookat_pixel");
  const std::optional<glm::dvec3> lookAt3d = meter.point("laser_lookat_3d");
  const std::optional<bool> meterAccounts = meter.boolean("account_first_and_last_bounces");
  if (meterAccounts && integratorAccounts && *meterAccounts != *integratorAccounts)
    document.fail(meter.propertyNode("account_first_and_last_bounces"),
                  "account_first_and_last_bounces differs from the integrator's");
  if (!meterAccounts && !integratorAccounts)
    meter.fail("give account_first_and_last_bounces (here or on transient_nlos_path): mitransient's default changed "
               "between versions (true on the sensor, false on the integrator), and it shifts every time bin");
  const bool accounts = meterAccounts ? *meterAccounts : *integratorAccounts;

  const std::vector<const XmlNode*> emitters = meter.objects("emitter");
  if (emitters.size() > 1) document.fail(*emitters[1], "an nlos_capture_meter takes one laser");
  const XmlNode* projector = emitters.empty() ? sceneProjector : emitters.front();
  if (!projector) meter.fail("no laser: put a projector emitter inside the nlos_capture_meter or in the scene");
  if (capture.confocal && (lookAtPixel || lookAt3d))
    document.fail(meter.propertyNode(lookAtPixel ? "laser_lookat_pixel" : "laser_lookat_3d"),
                  "a confocal capture aims the laser at every grid point in turn; laser_lookat_* names a single point");
  if (!capture.confocal && !lookAtPixel && !lookAt3d)
    meter.fail("give laser_lookat_pixel or laser_lookat_3d: where the laser hits the wall");
  if (lookAtPixel && lookAt3d) meter.fail("give laser_lookat_pixel or laser_lookat_3d, not both");

  // The wall: the rectangle's uv (the film's pixel centres) mapped through to_world, as
  // mitransient's sample_position does; its front face (flip_normals turns it around) faces the
  // hidden scene.
  const glm::dmat4& m = wall.toWorld;
  glm::dvec3 normal = glm::normalize(glm::transpose(glm::inverse(glm::dmat3(m))) * glm::dvec3(0, 0, 1));
  if (wall.flipNormals) normal = -normal;
  auto wallPoint = [&](double u, double v) { return applyPoint(m, glm::dvec3(2.0 * u - 1.0, 2.0 * v - 1.0, 0.0)); };
  const glm::dvec3 centre = wallPoint(0.5, 0.5);
  if (glm::dot(sensorOrigin - centre, normal) < 0) {
    if (!wall.twoSided)
      document.fail(meter.has("sensor_origin") ? meter.propertyNode("sensor_origin") : meter.node(),
                    "sensor_origin is behind the relay wall's front face, and the wall's BSDF is one-sided: Mitsuba "
                    "would measure nothing");
    normal = -normal;
  }

  glm::dvec3 spot = centre;
  if (lookAtPixel) {
    const glm::dvec3 p = *lookAtPixel;
    if (p.z != 0 || p.x < 0 || p.x > columns || p.y < 0 || p.y > rows)
      document.fail(meter.propertyNode("laser_lookat_pixel"), "laser_lookat_pixel must be (x, y, 0) with 0 <= x <= " +
                                                                  std::to_string(columns) + " and 0 <= y <= " + std::to_string(rows));
    spot = wallPoint(p.x / columns, p.y / rows);
  } else if (lookAt3d) {
    const glm::dvec3 local = glm::dvec3(glm::inverse(m) * glm::dvec4(*lookAt3d, 1.0));
    constexpr double kOnWall = 1e-5;
    if (!(std::abs(local.z) <= kOnWall && std::abs(local.x) <= 1 + kOnWall && std::abs(local.y) <= 1 + kOnWall))
      document.fail(meter.propertyNode("laser_lookat_3d"), "laser_lookat_3d is not a point of the relay wall");
    spot = *lookAt3d;
  }
  if (glm::dot(laserOrigin - spot, normal) < 0)
    document.fail(meter.has("laser_origin") ? meter.propertyNode("laser_origin") : meter.node(),
                  "laser_origin is on the other side of the relay wall from sensor_origin");

  capture.laser.name = "laser";
  if (const std::string* id = projector->attribute("id")) {
    capture.laser.name = *id;
    capture.laserNamedById = true;
  }
  capture.laser.intensity = float(laserIntensity(document, *projector, wall.albedo));
  capture.laser.position = glm::vec3(spot);

  Scan& scan = capture.scan;
  scan.grid = true;
  scan.columns = columns;
  scan.rows = rows;
  scan.views.reserve(size_t(columns) * rows);
  for (uint32_t j = 0; j < rows; ++j)
    for (uint32_t i = 0; i < columns; ++i) {
      const glm::dvec3 point = wallPoint((i + 0.5) / columns, (j + 0.5) / rows);
      const glm::dvec3 laser = capture.confocal ? point : spot;
      SceneView view;
      view.position = glm::vec3(point);
      view.normal = glm::vec3(normal);
      if (capture.confocal) view.lightPositions.emplace_back(laserIndex, glm::vec3(point));
      if (accounts) view.pathOffset = float(glm::distance(sensorOrigin, point) + glm::distance(laserOrigin, laser));
      if (!allFinite({*view.position})) meter.fail("a grid point of the relay wall is past the float range");
      if (!(view.pathOffset <= kMaxPathOffset))
        meter.fail("the legs to the wall and back are longer than " + formatNumber(kMaxPathOffset) + " m");
      scan.views.push_back(std::move(view));
    }
  if (capture.confocal) capture.laser.position = *scan.views.front().position;
  capture.camera.type = CameraType::PointSensor;
  capture.camera.position = *scan.views.front().position;
  capture.camera.normal = glm::vec3(normal);
  capture.camera.width = capture.camera.height = 1;
  meter.finish();
  return capture;
}

}  // namespace vktg
