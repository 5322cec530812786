// tal's HDF5 layout (tal/io/capture_data.py, tal/enums.py): one root dataset per field of
// NLOSCaptureData. H has time on axis 0; H_format and the grid formats are h5py enumerations (or
// plain integers) with tal's values; t_accounts_first_and_last_bounces is h5py's boolean; tal
// writes None as a dataset without elements.
#include <cmath>

#include "io/capture_formats.h"
#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg::io {
namespace {

using hdf5::Dataset;
using hdf5::describeDims;
using hdf5::failAt;
using hdf5::File;

CaptureHFormat readHFormat(const File& file) {
  const Dataset d = hdf5::openDataset(file, "H_format");
  const int64_t value = hdf5::readInteger(file, d);
  if (value >= 1 && value <= 4) return CaptureHFormat(value);
  for (const auto& [name, v] : talHFormatMembers())
    if (v == value) {
      if (value == 0) failAt(file, "H_format", "0 (UNKNOWN): tal's value for a format not yet known, not an axis order");
      failAt(file, "H_format", std::to_string(value) + " (" + name +
                                   ") is frequency-domain data; vktg reads time-domain captures (T_Sx_Sy, "
                                   "T_Lx_Ly_Sx_Sy, T_Si, T_Li_Si)");
    }
  failAt(file, "H_format", "unknown H_format " + std::to_string(value) + " (tal's are 1 T_Sx_Sy, 2 T_Lx_Ly_Sx_Sy, 3 T_Si, 4 T_Li_Si)");
}

const char* axesOf(CaptureHFormat f) {
  switch (f) {
    case CaptureHFormat::T_Sx_Sy: return "(T, Sx, Sy)";
    case CaptureHFormat::T_Lx_Ly_Sx_Sy: return "(T, Lx, Ly, Sx, Sy)";
    case CaptureHFormat::T_Si: return "(T, Si)";
    case CaptureHFormat::T_Li_Si: return "(T, Li, Si)";
  }
  return "";
}

// A grid's points from DATASET of shape (X, Y, 3) or (N, 3), as its format dataset says.
std::vector<glm::vec3> readPoints(const File& file, const Dataset& d) {
  const std::vector<float> values = hdf5::readFloats(file, d);
  std::vector<glm::vec3> points(values.size() / 3);
  for (size_t k = 0; k < points.size(); ++k) points[k] = {values[3 * k], values[3 * k + 1], values[3 * k + 2]};
  return points;
}

CaptureGrid readGrid(const File& file, const std::string& prefix) {
  const std::string xyzName = prefix + "_grid_xyz", normalsName = prefix + "_grid_normals", formatName = prefix + "_grid_format";
  const int64_t format = hdf5::readInteger(file, hdf5::openDataset(file, formatName));
  if (format != kGridFormatN3 && format != kGridFormatXY3)
    failAt(file, formatName, format == 0 ? "0 (UNKNOWN): tal's value for a layout not yet known, not a grid layout"
                                         : "unknown grid format " + std::to_string(format) + " (tal's are 1 N_3, 2 X_Y_3)");
  const bool xy = format == kGridFormatXY3;
  const Dataset xyz = hdf5::openDataset(file, xyzName);
  const size_t rank = xy ? 3 : 2;
  if (xyz.dims.size() != rank || xyz.dims.back() != 3)
    failAt(file, xyzName, "shape " + describeDims(xyz.dims) + " is not " + (xy ? "(X, Y, 3)" : "(N, 3)") + " as " +
                              formatName + " " + (xy ? "X_Y_3" : "N_3") + " says");
  const Dataset normals = hdf5::openDataset(file, normalsName);
  if (normals.dims != xyz.dims)
    failAt(file, normalsName, "shape " + describeDims(normals.dims) + " differs from " + xyzName + "'s " + describeDims(xyz.dims));
  CaptureGrid grid;
  for (size_t a = 0; a + 1 < rank; ++a) grid.shape.push_back(uint32_t(xyz.dims[a]));
  grid.positions = readPoints(file, xyz);
  grid.normals = readPoints(file, normals);
  return grid;
}

// sensor_xyz / laser_xyz: three numbers (tal reshapes them to 3), or absent / None.
std::optional<glm::vec3> readDevice(const File& file, const std::string& name) {
  const std::optional<Dataset> d = hdf5::openOptional(file, name);
  if (!d || d->null) return std::nullopt;
  if (d->count() != 3) failAt(file, name, "expected 3 numbers (x, y, z), got shape " + describeDims(d->dims));
  const std::vector<float> v = hdf5::readFloats(file, *d);
  return glm::vec3(v[0], v[1], v[2]);
}

std::string sensorAxesText(const Capture& c) {
  std::vector<uint64_t> axes(c.dims.end() - (c.hFormat == CaptureHFormat::T_Sx_Sy || c.hFormat == CaptureHFormat::T_Lx_Ly_Sx_Sy ? 2 : 1),
                             c.dims.end());
  return describeDims(axes);
}

}  // namespace

const std::vector<std::pair<std::string, int32_t>>& talHFormatMembers() {
  static const std::vector<std::pair<std::string, int32_t>> members = {
      {"UNKNOWN", 0},  {"T_Sx_Sy", 1},        {"T_Lx_Ly_Sx_Sy", 2}, {"T_Si", 3},     {"T_Li_Si", 4},
      {"F_Sx_Sy", 10}, {"F_Lx_Ly_Sx_Sy", 11}, {"F_Si", 12},         {"F_Li_Si", 13}};
  return members;
}

const std::vector<std::pair<std::string, int32_t>>& talGridFormatMembers() {
  static const std::vector<std::pair<std::string, int32_t>> members = {{"UNKNOWN", 0}, {"N_3", 1}, {"X_Y_3", 2}};
  return members;
}

Capture readTalCapture(const File& file) {
  Capture c;
  c.hFormat = readHFormat(file);
  const Dataset H = hdf5::openDataset(file, "H");
  const size_t rank = c.hFormat == CaptureHFormat::T_Lx_Ly_Sx_Sy ? 5 : c.hFormat == CaptureHFormat::T_Si ? 2 : 3;
  if (H.dims.size() != rank)
    failAt(file, "H", "shape " + describeDims(H.dims) + " has rank " + std::to_string(H.dims.size()) + ", but H_format " +
                          hFormatName(c.hFormat) + " has axes " + axesOf(c.hFormat));
  for (uint64_t d : H.dims) {
    if (d == 0) failAt(file, "H", "empty: shape " + describeDims(H.dims));
    c.dims.push_back(uint32_t(d));  // each below kMaxValues (openDataset)
  }
  c.sensor = readGrid(file, "sensor");
  c.laser = readGrid(file, "laser");
  // The grids against H before H's values are read.
  const bool sensorGrid = c.hFormat == CaptureHFormat::T_Sx_Sy || c.hFormat == CaptureHFormat::T_Lx_Ly_Sx_Sy;
  if (c.sensor.xy() != sensorGrid)
    failAt(file, "sensor_grid_format", std::string(c.sensor.xy() ? "X_Y_3" : "N_3") + ", but H_format " + hFormatName(c.hFormat) +
                                           " has " + (sensorGrid ? "a grid (Sx, Sy)" : "a list (Si)") + " of sensor points");
  const std::vector<uint32_t> sensorAxes(c.dims.end() - (sensorGrid ? 2 : 1), c.dims.end());
  if (c.sensor.shape != sensorAxes)
    failAt(file, "sensor_grid_xyz", "its grid " + describeDims({c.sensor.shape.begin(), c.sensor.shape.end()}) +
                                        " does not match H's sensor axes " + sensorAxesText(c) + " (H " + describeDims(H.dims) +
                                        ", H_format " + hFormatName(c.hFormat) + " " + axesOf(c.hFormat) + ")");
  if (c.hFormat == CaptureHFormat::T_Lx_Ly_Sx_Sy || c.hFormat == CaptureHFormat::T_Li_Si) {
    const std::vector<uint32_t> laserAxes(c.dims.begin() + 1, c.dims.end() - (sensorGrid ? 2 : 1));
    if (c.laser.shape != laserAxes)
      failAt(file, "laser_grid_xyz", "its grid " + describeDims({c.laser.shape.begin(), c.laser.shape.end()}) +
                                         " does not match H's laser axes " + describeDims({laserAxes.begin(), laserAxes.end()}) +
                                         " (H_format " + hFormatName(c.hFormat) + " " + axesOf(c.hFormat) + ")");
  } else if (c.laser.size() != 1 && c.laser.shape != c.sensor.shape) {
    failAt(file, "laser_grid_xyz",
           "its grid " + describeDims({c.laser.shape.begin(), c.laser.shape.end()}) + ": without laser axes in H (H_format " +
               hFormatName(c.hFormat) + ") the laser is one point or one per sensor point " +
               describeDims({c.sensor.shape.begin(), c.sensor.shape.end()}));
  }
  c.deltaT = hdf5::readScalar(file, hdf5::openDataset(file, "delta_t"));
  if (!(c.deltaT > 0)) failAt(file, "delta_t", "must be > 0 (the bin width in metres of optical path), got " + formatNumber(c.deltaT));
  c.tStart = hdf5::readScalar(file, hdf5::openDataset(file, "t_start"));
  const int64_t legs = hdf5::readInteger(file, hdf5::openDataset(file, "t_accounts_first_and_last_bounces"));
  if (legs != 0 && legs != 1)
    failAt(file, "t_accounts_first_and_last_bounces", std::to_string(legs) + " is not a boolean (0 or 1)");
  c.tAccountsFirstAndLastBounces = legs == 1;
  c.sensorXyz = readDevice(file, "sensor_xyz");
  c.laserXyz = readDevice(file, "laser_xyz");
  if (c.tAccountsFirstAndLastBounces)
    for (auto [device, name] : {std::pair{&c.sensorXyz, "sensor_xyz"}, std::pair{&c.laserXyz, "laser_xyz"}})
      if (!device->has_value())
        failAt(file, name, "missing or empty, but t_accounts_first_and_last_bounces is true: the legs to and from the wall need "
                           "both devices' positions");
  if (const std::optional<Dataset> info = hdf5::openOptional(file, "scene_info"))
    c.sceneInfo = hdf5::readString(file, *info).value_or("");
  c.H = hdf5::readFloats(file, H);
  c.confocal = c.hFormat != CaptureHFormat::T_Lx_Ly_Sx_Sy && c.hFormat != CaptureHFormat::T_Li_Si && gridsCoincide(c.laser, c.sensor);
  validateCapture(c, file.name);
  return c;
}

}  // namespace vktg::io
