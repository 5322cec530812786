// Captures in general: reading by layout, the checks every capture passes, writing tal's layout,
// and H as the image of a point-sensor scan.
#include "io/nlos_capture.h"

#include <cmath>

#include "io/capture_formats.h"
#include "scene/scene_values.h"
#include "vktg/error.h"
#include "vktg/gate.h"

namespace vktg {
namespace {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "grid points are written as float triples");

bool hasLaserAxes(CaptureHFormat f) { return f == CaptureHFormat::T_Lx_Ly_Sx_Sy || f == CaptureHFormat::T_Li_Si; }
bool sensorIsGrid(CaptureHFormat f) { return f == CaptureHFormat::T_Sx_Sy || f == CaptureHFormat::T_Lx_Ly_Sx_Sy; }

size_t expectedRank(CaptureHFormat f) {
  switch (f) {
    case CaptureHFormat::T_Sx_Sy: return 3;
    case CaptureHFormat::T_Lx_Ly_Sx_Sy: return 5;
    case CaptureHFormat::T_Si: return 2;
    case CaptureHFormat::T_Li_Si: return 3;
  }
  return 0;
}

std::string describeShape(const std::vector<uint32_t>& shape) {
  return io::hdf5::describeDims(std::vector<uint64_t>(shape.begin(), shape.end()));
}

std::string describeVec(glm::vec3 v) {
  std::string text = "(";
  text += formatNumber(v.x) + ", " + formatNumber(v.y) + ", " + formatNumber(v.z) + ")";
  return text;
}

// Points of a grid's shape, 0 if a side is 0.
uint64_t points(const std::vector<uint32_t>& shape) {
  uint64_t n = 1;
  for (uint32_t s : shape) n *= s;
  return n;
}

void validateGrid(const CaptureGrid& grid, const std::string& file, const std::string& prefix) {
  const std::string xyz = prefix + "_grid_xyz", normals = prefix + "_grid_normals";
  if (grid.shape.empty() || grid.shape.size() > 2) fail(file, xyz, "a grid has shape (X, Y) or (N): got " + describeShape(grid.shape));
  if (points(grid.shape) == 0) fail(file, xyz, "empty grid " + describeShape(grid.shape));
  if (grid.positions.size() != points(grid.shape))
    fail(file, xyz, std::to_string(grid.positions.size()) + " points for shape " + describeShape(grid.shape));
  if (grid.normals.size() != grid.positions.size())
    fail(file, normals, std::to_string(grid.normals.size()) + " normals for " + std::to_string(grid.positions.size()) + " points");
  for (size_t k = 0; k < grid.positions.size(); ++k) {
    const glm::vec3 p = grid.positions[k], n = grid.normals[k];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(file, xyz, "non-finite point " + describeVec(p) + " at " + std::to_string(k));
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      fail(file, normals, "non-finite normal " + describeVec(n) + " at " + std::to_string(k));
  }
}

}  // namespace

const char* hFormatName(CaptureHFormat format) {
  switch (format) {
    case CaptureHFormat::T_Sx_Sy: return "T_Sx_Sy";
    case CaptureHFormat::T_Lx_Ly_Sx_Sy: return "T_Lx_Ly_Sx_Sy";
    case CaptureHFormat::T_Si: return "T_Si";
    case CaptureHFormat::T_Li_Si: return "T_Li_Si";
  }
  return "unknown";
}

bool gridsCoincide(const CaptureGrid& laser, const CaptureGrid& sensor) {
  if (laser.shape != sensor.shape || laser.positions.size() != sensor.positions.size()) return false;
  for (size_t k = 0; k < laser.positions.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const double l = laser.positions[k][c], s = sensor.positions[k][c];
      if (!(std::abs(s - l) <= 1e-8 + 1e-5 * std::abs(l))) return false;
    }
  return true;
}

void validateCapture(const Capture& c, const std::string& file) {
  const int32_t format = int32_t(c.hFormat);
  if (format < 1 || format > 4) fail(file, "H_format", "unknown H_format " + std::to_string(format));
  const size_t rank = expectedRank(c.hFormat);
  if (c.dims.size() != rank)
    fail(file, "H", "shape " + describeShape(c.dims) + " has rank " + std::to_string(c.dims.size()) + ", but H_format " +
                        hFormatName(c.hFormat) + " has " + std::to_string(rank) + " axes");
  uint64_t values = 1;
  for (uint32_t d : c.dims) {
    if (d == 0) fail(file, "H", "empty: shape " + describeShape(c.dims));
    values *= d;
    if (values > io::hdf5::kMaxValues) fail(file, "H", "shape " + describeShape(c.dims) + " holds too many values");
  }
  if (c.H.size() != values)
    fail(file, "H", std::to_string(c.H.size()) + " values for shape " + describeShape(c.dims));
  for (size_t i = 0; i < c.H.size(); ++i)
    if (!std::isfinite(c.H[i])) fail(file, "H", "non-finite value " + formatNumber(c.H[i]) + " at flat index " + std::to_string(i));

  validateGrid(c.sensor, file, "sensor");
  validateGrid(c.laser, file, "laser");
  // The sensor axes are H's last one or two.
  const std::vector<uint32_t> sensorAxes = sensorIsGrid(c.hFormat) ? std::vector<uint32_t>{c.dims[rank - 2], c.dims[rank - 1]}
                                                                     : std::vector<uint32_t>{c.dims[rank - 1]};
  if (c.sensor.shape != sensorAxes)
    fail(file, "sensor_grid_xyz",
         "shape " + describeShape(c.sensor.shape) + " does not match H's sensor axes " + describeShape(sensorAxes) +
             " (H_format " + hFormatName(c.hFormat) + ", H " + describeShape(c.dims) + ")");
  if (hasLaserAxes(c.hFormat)) {
    const std::vector<uint32_t> laserAxes = c.hFormat == CaptureHFormat::T_Lx_Ly_Sx_Sy
                                                ? std::vector<uint32_t>{c.dims[1], c.dims[2]}
                                                : std::vector<uint32_t>{c.dims[1]};
    if (c.laser.shape != laserAxes)
      fail(file, "laser_grid_xyz", "shape " + describeShape(c.laser.shape) + " does not match H's laser axes " +
                                       describeShape(laserAxes) + " (H_format " + hFormatName(c.hFormat) + ")");
  } else if (c.laser.size() != 1 && c.laser.shape != c.sensor.shape) {
    fail(file, "laser_grid_xyz",
         "shape " + describeShape(c.laser.shape) + ": without laser axes in H (H_format " + hFormatName(c.hFormat) +
             ") the laser is one point or one per sensor point " + describeShape(c.sensor.shape));
  }
  if (!(std::isfinite(c.deltaT) && c.deltaT > 0))
    fail(file, "delta_t", "must be > 0 (the bin width in metres of optical path), got " + formatNumber(c.deltaT));
  if (!std::isfinite(c.tStart)) fail(file, "t_start", "non-finite value " + formatNumber(c.tStart));
  for (auto [device, name] : {std::pair{&c.sensorXyz, "sensor_xyz"}, std::pair{&c.laserXyz, "laser_xyz"}}) {
    if (device->has_value()) {
      const glm::vec3 p = **device;
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail(file, name, "non-finite position " + describeVec(p));
    } else if (c.tAccountsFirstAndLastBounces) {
      fail(file, name, "missing, but t_accounts_first_and_last_bounces is true: the legs to and from the wall need both devices' positions");
    }
  }
  const bool confocal = !hasLaserAxes(c.hFormat) && gridsCoincide(c.laser, c.sensor);
  if (c.confocal != confocal)
    fail(file, "laser_grid_xyz", std::string("the capture is marked ") + (c.confocal ? "" : "not ") +
                                     "confocal, but its laser grid " + (confocal ? "is" : "is not") + " its sensor grid");
}

namespace {

Capture readOpenCapture(const io::hdf5::File& file) {
  // tal's detection order (tal/io/format.py): the Zaragoza dataset's "data" first, then tal's "H"
  // (or its H_format, so that a tal file without H says so).
  if (io::hdf5::hasLink(file, "data")) return io::readZaragozaCapture(file);
  if (io::hdf5::hasLink(file, "H") || io::hdf5::hasLink(file, "H_format")) return io::readTalCapture(file);
  fail(file.name, "", "neither a tal capture (no dataset \"H\") nor a Zaragoza NLOS dataset file (no dataset \"data\")");
}

}  // namespace

Capture readCapture(const std::filesystem::path& path) {
  const io::hdf5::File file = io::hdf5::openFile(path.string());
  return readOpenCapture(file);
}

Capture readCaptureImage(const std::string& bytes, const std::string& name) {
  const io::hdf5::File file = io::hdf5::openImage(bytes, name);
  return readOpenCapture(file);
}

void writeCaptureTal(const std::filesystem::path& path, const Capture& c) {
  const std::string name = path.string();
  validateCapture(c, name);
  io::hdf5::Writer w(name);
  auto dimsOf = [](const std::vector<uint32_t>& shape, bool withComponents) {
    std::vector<uint64_t> dims(shape.begin(), shape.end());
    if (withComponents) dims.push_back(3);
    return dims;
  };
  auto device = [&](const char* dataset, const std::optional<glm::vec3>& p) {
    if (p) w.floats(dataset, {3}, &p->x);
    else w.empty(dataset);  // tal's None
  };
  auto grid = [&](const std::string& prefix, const CaptureGrid& g) {
    w.floats(prefix + "_grid_xyz", dimsOf(g.shape, true), &g.positions.front().x);
    w.floats(prefix + "_grid_normals", dimsOf(g.shape, true), &g.normals.front().x);
    w.enumeration(prefix + "_grid_format", io::talGridFormatMembers(), g.xy() ? io::kGridFormatXY3 : io::kGridFormatN3);
  };
  // In the order of tal's NLOSCaptureData fields, as tal's write_capture lays them out.
  w.floats("H", dimsOf(c.dims, false), c.H.data());
  w.enumeration("H_format", io::talHFormatMembers(), int32_t(c.hFormat));
  device("sensor_xyz", c.sensorXyz);
  grid("sensor", c.sensor);
  device("laser_xyz", c.laserXyz);
  grid("laser", c.laser);
  w.empty("volume_format");  // deprecated in tal; its render leaves it None
  w.doubleScalar("delta_t", c.deltaT);
  w.doubleScalar("t_start", c.tStart);
  w.boolean("t_accounts_first_and_last_bounces", c.tAccountsFirstAndLastBounces);
  // tal's reader needs a mapping here (it asks it whether the data is polarised).
  w.string("scene_info", c.sceneInfo.empty() ? "{}\n" : c.sceneInfo);
  writeFileAtomic(path, w.image());
}

std::vector<CaptureView> captureViews(const Capture& c) {
  std::vector<CaptureView> views;
  const size_t sensors = c.sensor.size();
  // A grid's sensor points row by row of the image (point (x, y) at x * Y + y in the grid's order).
  auto sensorAt = [&](size_t k) -> size_t {
    if (!c.sensor.xy()) return k;
    const size_t columns = c.sensor.shape[0], rows = c.sensor.shape[1];
    return (k % columns) * rows + k / columns;
  };
  auto laserAt = [&](size_t l) -> size_t {
    if (!c.laser.xy()) return l;
    const size_t columns = c.laser.shape[0], rows = c.laser.shape[1];
    return (l % columns) * rows + l / columns;
  };
  if (hasLaserAxes(c.hFormat)) {
    for (size_t l = 0; l < c.laser.size(); ++l)
      for (size_t k = 0; k < sensors; ++k) views.push_back({sensorAt(k), laserAt(l)});
  } else {
    for (size_t k = 0; k < sensors; ++k) views.push_back({sensorAt(k), c.laser.size() == 1 ? 0 : sensorAt(k)});
  }
  return views;
}

glm::uvec2 captureImageSize(const Capture& c) {
  if (c.hFormat == CaptureHFormat::T_Sx_Sy) return {c.sensor.shape[0], c.sensor.shape[1]};
  return {uint32_t(c.sensor.size() * (hasLaserAxes(c.hFormat) ? c.laser.size() : 1)), 1};
}

ImageSet captureImage(const Capture& c) {
  const glm::uvec2 size = captureImageSize(c);
  Gate bins;
  bins.type = GateType::Bins;
  bins.binStart = c.tStart;
  bins.binWidth = c.deltaT;
  bins.binCount = c.bins();
  ImageSet image{size.x, size.y, {}};
  const std::vector<CaptureView> views = captureViews(c);
  const size_t sensors = c.sensor.size(), perBin = c.H.size() / c.bins();
  for (uint32_t t = 0; t < c.bins(); ++t) {
    ImageLayer layer{bins.layerName(t), std::vector<float>(views.size())};
    for (size_t k = 0; k < views.size(); ++k) {
      const size_t laser = hasLaserAxes(c.hFormat) ? views[k].laser : 0;
      layer.pixels[k] = c.H[t * perBin + laser * sensors + views[k].sensor];
    }
    image.layers.push_back(std::move(layer));
  }
  return image;
}

std::vector<float> captureH(const ImageSet& image, CaptureHFormat format) {
  if (format != CaptureHFormat::T_Sx_Sy && format != CaptureHFormat::T_Si)
    fail("", "H_format", std::string("an image is written as T_Sx_Sy or T_Si, not ") + hFormatName(format));
  const size_t columns = image.width, rows = image.height, pixels = columns * rows;
  std::vector<float> H(pixels * image.layers.size());
  for (size_t t = 0; t < image.layers.size(); ++t)
    for (size_t y = 0; y < rows; ++y)
      for (size_t x = 0; x < columns; ++x) H[t * pixels + x * rows + y] = image.layers[t].pixels.at(y * columns + x);
  return H;
}

}  // namespace vktg
