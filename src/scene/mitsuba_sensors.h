// What a Mitsuba scene's sensor says (docs/scene-format.md, "Mitsuba 3 XML"): its film (image size
// and, for mitransient's transient_hdr_film, the time bins), its sampler (samples per pixel), and
// either a perspective camera or mitransient's nlos_capture_meter on a relay wall, which becomes a
// point sensor and a scan of the wall's grid of points.
#pragma once
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "scene/mitsuba_plugin.h"
#include "scene/scan.h"
#include "vktg/gate.h"
#include "vktg/scene.h"

namespace vktg {

struct FilmSettings {
  uint32_t width = 768, height = 576;  // Mitsuba's default film
  Gate gate;                           // steady for hdrfilm; the bins of a transient_hdr_film
  bool transient = false;              // a transient_hdr_film
  const XmlNode* node = nullptr;       // nullptr: the default film
};

struct SamplerSettings {
  uint32_t spp = 4;  // Mitsuba's default sampler takes 4 samples per pixel
  uint32_t seed = 0;
};

// <film type="hdrfilm"> or <film type="transient_hdr_film">; nullptr gives Mitsuba's default film.
FilmSettings readFilm(const XmlDocument& document, const XmlNode* film);
// <sampler type="independent"> (or another of Mitsuba's samplers); nullptr gives the default.
SamplerSettings readSampler(const XmlDocument& document, const XmlNode* sampler);

// A perspective sensor's camera: pose from to_world (rigid: no scale, no mirror), vertical field of
// view from fov / fov_axis or focal_length and the film's aspect, image size from the film.
Camera readPerspectiveCamera(PluginElement& sensor, const FilmSettings& film);

// The relay wall an nlos_capture_meter sits on: a rectangle with a diffuse BSDF.
struct RelayWall {
  glm::dmat4 toWorld{1.0};
  bool flipNormals = false;
  double albedo = 0.5;     // the wall's diffuse reflectance
  bool twoSided = false;   // a twosided BSDF: the sensor may look from either side
};

struct NlosCapture {
  Camera camera;           // a point sensor at the first grid point
  Scan scan;               // the film's width x height grid of wall points, row by row
  PointLight laser;        // the laser's spot on the wall, as a point light
  bool laserNamedById = false;  // its name is the projector's id (else "laser", to be made unique)
  bool confocal = false;   // the laser moves with the sensor (each view places it)
  FilmSettings film;
  SamplerSettings sampler;
};

// The nlos_capture_meter `meter` on `wall`. The laser is the projector inside the meter or, when it
// has none, `sceneProjector` (the scene's own projector, or nullptr). `integratorAccounts` is
// transient_nlos_path's account_first_and_last_bounces, if it gives one. `laserIndex` is the index
// the laser will have among the scene's point lights (the views of a confocal scan move it).
NlosCapture readNlosCaptureMeter(PluginElement& meter, const RelayWall& wall, const XmlNode* sceneProjector,
                                 std::optional<bool> integratorAccounts, uint32_t laserIndex);

}  // namespace vktg
