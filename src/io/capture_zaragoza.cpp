// The Zaragoza NLOS dataset's HDF5 layout (graphics.unizar.es/nlos_dataset), mapped to tal's terms
// as tal's own converter does (tal/io/format.py, HDF5_ZNLOS): the transient in `data` summed over
// its bounce and colour axes, the grids from cameraGrid* and laserGrid*, the devices from
// cameraPosition and laserPosition, deltaT and t0 in metres of optical path, and times that count
// the legs from the devices to the wall (t_accounts_first_and_last_bounces).
//
// Axis order. The dataset's documentation gives its arrays in column-major order, as MATLAB reads
// them: data (X, Y, bounces, T, colours) for a confocal scan, (laser X, Y, sensor X, Y, bounces, T,
// colours) for an exhaustive one, grids (X, Y, 3). A file whose root attribute "data order" is
// "row-major" stores them in that order as C sees it; otherwise (no attribute, or "column-major")
// HDF5's C order is the reverse, e.g. data (colours, T, bounces, Y, X). The dataset's MATLAB and
// C++ readers (NLOSData) decide by the attribute; tal's converter guesses from which axes have equal
// sizes and agrees with this for confocal data. Sensor X is H's Sx and sensor Y its Sy, and the
// grids follow the same axes, so that H[t, x, y] is measured at grid point (x, y).
#include <cfloat>
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

std::vector<uint64_t> logicalDims(const std::vector<uint64_t>& dims, bool rowMajor) {
  return rowMajor ? dims : std::vector<uint64_t>(dims.rbegin(), dims.rend());
}

const char* orderName(bool rowMajor) { return rowMajor ? "row-major" : "column-major"; }

std::vector<glm::vec3> readGridValues(const File& file, const Dataset& d, bool rowMajor, uint64_t columns, uint64_t rows) {
  const std::vector<float> v = hdf5::readFloats(file, d);
  std::vector<glm::vec3> points(size_t(columns * rows));
  for (uint64_t x = 0; x < columns; ++x)
    for (uint64_t y = 0; y < rows; ++y)
      for (uint64_t c = 0; c < 3; ++c)
        points[size_t(x * rows + y)][int(c)] =
            v[size_t(rowMajor ? (x * rows + y) * 3 + c : c * rows * columns + y * columns + x)];
  return points;
}

// A grid (X, Y, 3) in the file's order whose (X, Y) is one of `accepted`.
CaptureGrid readGrid(const File& file, const std::string& positionsName, const std::string& normalsName, bool rowMajor,
                     const std::vector<std::vector<uint32_t>>& accepted, const std::string& against) {
  const Dataset positions = hdf5::openDataset(file, positionsName);
  const std::vector<uint64_t> logical = logicalDims(positions.dims, rowMajor);
  const std::string expected = rowMajor ? "(X, Y, 3)" : "(3, Y, X) in C order, (X, Y, 3) column-major";
  if (logical.size() != 3 || logical[2] != 3)
    failAt(file, positionsName, "shape " + describeDims(positions.dims) + " is not " + expected + " (" + orderName(rowMajor) + " file)");
  CaptureGrid grid;
  grid.shape = {uint32_t(logical[0]), uint32_t(logical[1])};
  bool fits = false;
  for (const std::vector<uint32_t>& shape : accepted) fits = fits || shape == grid.shape;
  if (!fits)
    failAt(file, positionsName, "its grid (X, Y) = " + describeDims({logical[0], logical[1]}) + " does not match " + against);
  const Dataset normals = hdf5::openDataset(file, normalsName);
  if (normals.dims != positions.dims)
    failAt(file, normalsName, "shape " + describeDims(normals.dims) + " differs from " + positionsName + "'s " + describeDims(positions.dims));
  grid.positions = readGridValues(file, positions, rowMajor, logical[0], logical[1]);
  grid.normals = readGridValues(file, normals, rowMajor, logical[0], logical[1]);
  return grid;
}

glm::vec3 readDevice(const File& file, const std::string& name) {
  const Dataset d = hdf5::openDataset(file, name);
  if (d.null || d.count() != 3) failAt(file, name, "expected 3 numbers (x, y, z), got shape " + describeDims(d.dims));
  const std::vector<float> v = hdf5::readFloats(file, d);
  return {v[0], v[1], v[2]};
}

}  // namespace

Capture readZaragozaCapture(const File& file) {
  bool rowMajor = false;
  if (const std::optional<std::string> order = hdf5::readRootStringAttribute(file, "data order")) {
    if (*order == "row-major") rowMajor = true;
    else if (*order != "column-major")
      failAt(file, "attribute \"data order\"", "\"" + *order + "\" is neither \"row-major\" nor \"column-major\"");
  }
  const Dataset data = hdf5::openDataset(file, "data");
  const size_t rank = data.dims.size();
  if (rank != 5 && rank != 7)
    failAt(file, "data", "shape " + describeDims(data.dims) + " has rank " + std::to_string(rank) +
                             "; a Zaragoza dataset's data has 5 axes (X, Y, bounces, T, colours: a confocal scan) or 7 "
                             "(laser X, Y, sensor X, Y, bounces, T, colours), column-major unless the file says row-major");
  for (uint64_t d : data.dims)
    if (d == 0) failAt(file, "data", "empty: shape " + describeDims(data.dims));
  const std::vector<uint64_t> L = logicalDims(data.dims, rowMajor);
  const bool exhaustive = rank == 7;
  const size_t s = exhaustive ? 2 : 0;  // the first sensor axis
  const uint64_t lx = exhaustive ? L[0] : 1, ly = exhaustive ? L[1] : 1, sx = L[s], sy = L[s + 1], bins = L[s + 3];
  const std::string orderNote = std::string(" (") + orderName(rowMajor) + " file)";

  Capture c;
  const std::vector<uint32_t> sensorAxes = {uint32_t(sx), uint32_t(sy)};
  c.sensor = readGrid(file, "cameraGridPositions", "cameraGridNormals", rowMajor, {sensorAxes},
                      "data's sensor axes (X, Y) = " + describeDims({sx, sy}) + orderNote);
  if (exhaustive)
    c.laser = readGrid(file, "laserGridPositions", "laserGridNormals", rowMajor, {{uint32_t(lx), uint32_t(ly)}},
                       "data's laser axes (X, Y) = " + describeDims({lx, ly}) + orderNote);
  else
    c.laser = readGrid(file, "laserGridPositions", "laserGridNormals", rowMajor, {sensorAxes, {1, 1}},
                       "data's sensor axes (X, Y) = " + describeDims({sx, sy}) + orderNote +
                           ", nor is it one point: confocal data has a laser point per sensor point");
  c.sensorXyz = readDevice(file, "cameraPosition");
  c.laserXyz = readDevice(file, "laserPosition");
  c.deltaT = hdf5::readScalar(file, hdf5::openDataset(file, "deltaT"));
  if (!(c.deltaT > 0)) failAt(file, "deltaT", "must be > 0 (the bin width in metres of optical path), got " + formatNumber(c.deltaT));
  c.tStart = hdf5::readScalar(file, hdf5::openDataset(file, "t0"));
  c.tAccountsFirstAndLastBounces = true;
  c.sceneInfo = "{original_format: HDF5_ZNLOS}\n";

  // H = data summed over bounces and colours, its axes (T, [Lx, Ly,] Sx, Sy); one laser point of an
  // exhaustive file is a T_Sx_Sy capture, as tal's converter squeezes it.
  const bool laserAxes = exhaustive && (lx > 1 || ly > 1);
  c.hFormat = laserAxes ? CaptureHFormat::T_Lx_Ly_Sx_Sy : CaptureHFormat::T_Sx_Sy;
  c.dims = laserAxes ? std::vector<uint32_t>{uint32_t(bins), uint32_t(lx), uint32_t(ly), uint32_t(sx), uint32_t(sy)}
                     : std::vector<uint32_t>{uint32_t(bins), uint32_t(sx), uint32_t(sy)};
  // Each logical axis's step in H (0: summed over).
  const uint64_t perBin = lx * ly * sx * sy;
  const std::vector<uint64_t> roleStride =
      exhaustive ? std::vector<uint64_t>{ly * sx * sy, sx * sy, sy, 1, 0, perBin, 0} : std::vector<uint64_t>{sy, 1, 0, perBin, 0};
  std::vector<uint64_t> stride(rank);
  for (size_t a = 0; a < rank; ++a) stride[a] = roleStride[rowMajor ? a : rank - 1 - a];
  c.H.assign(size_t(bins * perBin), 0.0f);
  std::vector<uint64_t> index(rank, 0);
  uint64_t out = 0;
  hdf5::readBlocks(file, data, [&](uint64_t first, const double* values, size_t count) {
    for (size_t i = 0; i < count; ++i) {
      const double v = values[i];
      if (!std::isfinite(v) || std::abs(v) > double(FLT_MAX))
        failAt(file, "data", "value " + formatNumber(v) + " at index " + describeDims(index) +
                                 (std::isfinite(v) ? " is outside the range of 32-bit floats" : " is not finite"));
      c.H[size_t(out)] += float(v);
      // The next C-order index (`first + i + 1`), and its place in H.
      for (size_t a = rank; a-- > 0;) {
        ++index[a];
        out += stride[a];
        if (index[a] < data.dims[a] || a == 0) break;
        out -= index[a] * stride[a];
        index[a] = 0;
      }
    }
    (void)first;
  });
  for (size_t i = 0; i < c.H.size(); ++i)
    if (!std::isfinite(c.H[i]))
      failAt(file, "data", "the sum over bounces and colours at flat index " + std::to_string(i) + " of H exceeds the range of 32-bit floats");
  c.confocal = !laserAxes && gridsCoincide(c.laser, c.sensor);
  validateCapture(c, file.name);
  return c;
}

}  // namespace vktg::io
