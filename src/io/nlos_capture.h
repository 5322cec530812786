// NLOS capture files (docs/scene-format.md, "NLOS captures (HDF5)"): the transients of a relay-wall
// scan with the geometry they were measured at, as tal (github.com/diegoroyo/tal, "HDF5_TAL")
// writes them, or as the Zaragoza NLOS dataset does. readCapture reads either (told apart by their
// datasets) into one Capture in tal's terms; writeCaptureTal writes tal's layout atomically. Every
// failure is one vktg::Error "FILE: DATASET: problem".
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vktg/image_io.h"

namespace vktg {

// tal's HFormat, with its integer values; the axes of H, time first. The frequency-domain formats
// (F_*) are not read.
enum class CaptureHFormat : int32_t { T_Sx_Sy = 1, T_Lx_Ly_Sx_Sy = 2, T_Si = 3, T_Li_Si = 4 };

const char* hFormatName(CaptureHFormat format);

// Points on the relay wall: a grid (tal's GridFormat X_Y_3, shape {X, Y}) or a list (N_3, {N}).
struct CaptureGrid {
  std::vector<uint32_t> shape;
  std::vector<glm::vec3> positions;  // C order of `shape`: point (x, y) of a grid at x * Y + y
  std::vector<glm::vec3> normals;    // the same order
  bool xy() const { return shape.size() == 2; }
  size_t size() const { return positions.size(); }
  bool operator==(const CaptureGrid&) const = default;
};

struct Capture {
  CaptureHFormat hFormat = CaptureHFormat::T_Sx_Sy;
  std::vector<uint32_t> dims;  // H's shape: (T, Sx, Sy), (T, Lx, Ly, Sx, Sy), (T, Si) or (T, Li, Si)
  std::vector<float> H;        // C order of dims
  CaptureGrid sensor, laser;   // the laser's: one point, or one per sensor point where H has no laser axes
  // The devices' own positions (not the wall points): the ends of the legs that
  // tAccountsFirstAndLastBounces counts. Absent in a file that does not need them.
  std::optional<glm::vec3> sensorXyz, laserXyz;
  double deltaT = 0;           // bin width, metres of optical path
  double tStart = 0;           // path length at the start of bin 0, metres
  // Whether the times count the legs laser -> first wall point and last wall point -> sensor.
  bool tAccountsFirstAndLastBounces = false;
  // Laser and sensor at the same wall points (H has no laser axes, the grids coincide).
  bool confocal = false;
  std::string sceneInfo;       // tal's scene_info (YAML text); kept, never interpreted

  uint32_t bins() const { return dims.empty() ? 0 : dims[0]; }
  bool operator==(const Capture&) const = default;
};

// Reads a tal HDF5 capture (a dataset "H") or a Zaragoza NLOS dataset file (a dataset "data").
Capture readCapture(const std::filesystem::path& path);
// The same from the bytes of an HDF5 file held in memory; `name` names it in errors.
Capture readCaptureImage(const std::string& bytes, const std::string& name);

// Writes tal's layout (datasets as tal's write_capture makes them) to a temporary file beside
// `path` and renames it into place. The capture is checked first (validateCapture).
void writeCaptureTal(const std::filesystem::path& path, const Capture& capture);

// The checks every capture read or written passes: H's rank and dims against hFormat and the grids,
// finite values, delta_t > 0, the confocal flag against the grids, the device positions when the
// times count the legs. Throws vktg::Error naming `file` and the dataset.
void validateCapture(const Capture& capture, const std::string& file);

// tal's is_confocal: no laser axes and the laser grid at the sensor grid's points (within 1e-5
// relative, 1e-8 absolute, numpy.allclose's tolerance).
bool gridsCoincide(const CaptureGrid& laser, const CaptureGrid& sensor);

// The measurements of a capture in the order of its image (captureImage): view k is the sensor
// point `sensor` with the laser at point `laser` (indices into the grids' positions). T_Sx_Sy: row
// by row of the sensor grid, point (x, y) at k = y * Sx + x; T_Si: in list order; with laser axes,
// every sensor point for the first laser point (its grid row by row too), then the next.
struct CaptureView {
  size_t sensor = 0, laser = 0;
};
std::vector<CaptureView> captureViews(const Capture& capture);
// The image's columns x rows: (Sx, Sy) for T_Sx_Sy, else (number of views, 1).
glm::uvec2 captureImageSize(const Capture& capture);

// A grid or list capture's H as the image `vktg render --scan` writes for a point sensor: T layers
// (named as `bins` gates name theirs), view k at pixel k of a columns x rows image. T_Sx_Sy: Sx
// columns, Sy rows, H[t, x, y] at pixel (x, y). T_Si: one row of Si. With laser axes, every
// (laser, sensor) pair is a view, laser by laser, one row.
ImageSet captureImage(const Capture& capture);
// The inverse for T_Sx_Sy and T_Si: H from such an image (dims from the image's size and layers).
std::vector<float> captureH(const ImageSet& image, CaptureHFormat format);

}  // namespace vktg
