// NLOS capture files (src/io/nlos_capture.h): what writeCaptureTal writes reads back equal; files
// laid out as tal and the Zaragoza dataset lay theirs out (written here with the HDF5 C API, with
// the types h5py gives tal's values) read with H's axes and the grids where those formats put them;
// every bad input is one vktg::Error naming the file, the dataset and the problem.
#include <hdf5.h>

#include <cmath>
#include <functional>
#include <limits>

#include "io/nlos_capture.h"
#include "support/file_test.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::expectError;

// Writes datasets the way tal's write_capture (through h5py) and the Zaragoza dataset's files hold
// them, and a few ways they must not.
class H5Writer {
 public:
  explicit H5Writer(const fs::path& path) : m_file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT)) {
    EXPECT_GE(m_file, 0);
  }
  ~H5Writer() { H5Fclose(m_file); }

  template <typename T>
  void data(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<T>& values, hid_t fileType,
            hid_t memoryType) {
    const hid_t space = dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    const hid_t d = H5Dcreate2(m_file, name.c_str(), fileType, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(d, 0) << name;
    if (!values.empty()) EXPECT_GE(H5Dwrite(d, memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << name;
    H5Dclose(d);
    H5Sclose(space);
  }
  void floats(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<float>& values) {
    data(name, dims, values, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT);
  }
  void doubles(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& values) {
    data(name, dims, values, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
  }
  void int64(const std::string& name, int64_t value) { data(name, {}, std::vector<int64_t>{value}, H5T_STD_I64LE, H5T_NATIVE_INT64); }
  // h5py.enum_dtype(..., basetype='i'), shape (1,): how tal writes H_format and the grid formats.
  void talEnum(const std::string& name, int32_t value) {
    const hid_t type = H5Tenum_create(H5T_NATIVE_INT32);
    for (auto [member, v] : std::vector<std::pair<const char*, int32_t>>{{"UNKNOWN", 0}, {"A", 1}, {"B", 2}, {"C", 3}, {"D", 4}, {"F", 10}}) {
      H5Tenum_insert(type, member, &v);
    }
    data(name, {1}, std::vector<int32_t>{value}, type, type);
    H5Tclose(type);
  }
  // numpy.bool_ through h5py: an int8 enumeration FALSE/TRUE, scalar.
  void boolean(const std::string& name, bool value) {
    const hid_t type = H5Tenum_create(H5T_NATIVE_INT8);
    const int8_t no = 0, yes = 1;
    H5Tenum_insert(type, "FALSE", &no);
    H5Tenum_insert(type, "TRUE", &yes);
    data(name, {}, std::vector<int8_t>{int8_t(value)}, type, type);
    H5Tclose(type);
  }
  void rootString(const std::string& attribute, const std::string& value) {
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, value.size());
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(m_file, attribute.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, value.data());
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
  }
  hid_t id() const { return m_file; }

 private:
  hid_t m_file;
};

// A 3-bin, 4 x 2 grid: H[t, x, y] = 100 t + 10 x + y, wall points at (x, y, 0) facing +z, the
// laser at the sensor's points (confocal), times without the legs.
void writeTalGrid(const fs::path& path, const std::function<void(H5Writer&)>& change = {}) {
  H5Writer w(path);
  std::vector<float> H, grid, normals;
  for (int t = 0; t < 3; ++t)
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 2; ++y) H.push_back(float(100 * t + 10 * x + y));
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y) {
      grid.insert(grid.end(), {0.25f * x, 0.5f * y, 0.0f});
      normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
    }
  w.floats("H", {3, 4, 2}, H);
  w.talEnum("H_format", 1);
  w.floats("sensor_xyz", {3}, {-0.5f, 0.0f, 0.25f});
  w.floats("sensor_grid_xyz", {4, 2, 3}, grid);
  w.floats("sensor_grid_normals", {4, 2, 3}, normals);
  w.talEnum("sensor_grid_format", 2);
  w.floats("laser_xyz", {3}, {-0.5f, 0.0f, 0.25f});
  w.floats("laser_grid_xyz", {4, 2, 3}, grid);
  w.floats("laser_grid_normals", {4, 2, 3}, normals);
  w.talEnum("laser_grid_format", 2);
  w.doubles("delta_t", {}, {0.003});
  w.doubles("t_start", {}, {0.5});
  w.boolean("t_accounts_first_and_last_bounces", false);
  if (change) change(w);
}

class NlosCaptureTest : public test::TempDirTest {};

TEST_F(NlosCaptureTest, TalGridReadsWithTimeFirstAndTheGridAlongHsAxes) {
  writeTalGrid(m_dir / "grid.hdf5");
  const Capture c = readCapture(m_dir / "grid.hdf5");
  EXPECT_EQ(c.hFormat, CaptureHFormat::T_Sx_Sy);
  EXPECT_EQ(c.dims, (std::vector<uint32_t>{3, 4, 2}));
  EXPECT_EQ(c.H[(2 * 4 + 3) * 2 + 1], 231.0f) << "H[t=2, x=3, y=1]";
  EXPECT_EQ(c.sensor.shape, (std::vector<uint32_t>{4, 2}));
  EXPECT_EQ(c.sensor.positions[3 * 2 + 1], glm::vec3(0.75f, 0.5f, 0.0f)) << "grid point (3, 1)";
  EXPECT_EQ(c.sensor.normals[5], glm::vec3(0, 0, 1));
  EXPECT_TRUE(c.confocal);
  EXPECT_FALSE(c.tAccountsFirstAndLastBounces);
  EXPECT_EQ(c.deltaT, 0.003);
  EXPECT_EQ(c.tStart, 0.5);
  ASSERT_TRUE(c.sensorXyz);
  EXPECT_EQ(*c.sensorXyz, glm::vec3(-0.5f, 0.0f, 0.25f));
  // As `vktg render --scan` lays out a grid: point (x, y) at pixel (x, y), a layer per bin.
  const ImageSet image = captureImage(c);
  ASSERT_EQ(image.width, 4u);
  ASSERT_EQ(image.height, 2u);
  ASSERT_EQ(image.layers.size(), 3u);
  EXPECT_EQ(image.layers[2].pixels[1 * 4 + 3], 231.0f);
  EXPECT_EQ(image.layers[1].pixels[0 * 4 + 2], 120.0f);
  EXPECT_EQ(captureH(image, CaptureHFormat::T_Sx_Sy), c.H);
  const std::vector<CaptureView> views = captureViews(c);
  ASSERT_EQ(views.size(), 8u);
  EXPECT_EQ(views[1 * 4 + 3].sensor, 3u * 2 + 1) << "view (3, 1) is grid point (3, 1)";
  EXPECT_EQ(views[1 * 4 + 3].laser, 3u * 2 + 1);
}

TEST_F(NlosCaptureTest, TalListReadsWithPlainIntegersAndOneLaserPoint) {
  {
    H5Writer w(m_dir / "list.h5");
    std::vector<float> H;
    for (int t = 0; t < 2; ++t)
      for (int s = 0; s < 5; ++s) H.push_back(float(10 * t + s));
    std::vector<float> grid, normals;
    for (int s = 0; s < 5; ++s) {
      grid.insert(grid.end(), {float(s), 0.0f, 1.0f});
      normals.insert(normals.end(), {0.0f, 1.0f, 0.0f});
    }
    w.floats("H", {2, 5}, H);
    w.int64("H_format", 3);
    w.floats("sensor_grid_xyz", {5, 3}, grid);
    w.floats("sensor_grid_normals", {5, 3}, normals);
    w.int64("sensor_grid_format", 1);
    w.floats("laser_grid_xyz", {1, 3}, {0.0f, 2.0f, 0.0f});
    w.floats("laser_grid_normals", {1, 3}, {0.0f, 1.0f, 0.0f});
    w.int64("laser_grid_format", 1);
    w.floats("sensor_xyz", {3}, {0.0f, 3.0f, 0.0f});
    w.floats("laser_xyz", {3}, {1.0f, 3.0f, 0.0f});
    w.floats("delta_t", {1}, {0.01f});
    w.doubles("t_start", {1, 1}, {0.0});
    w.int64("t_accounts_first_and_last_bounces", 1);
  }
  const Capture c = readCapture(m_dir / "list.h5");
  EXPECT_EQ(c.hFormat, CaptureHFormat::T_Si);
  EXPECT_EQ(c.H[1 * 5 + 3], 13.0f);
  EXPECT_FALSE(c.confocal);
  EXPECT_TRUE(c.tAccountsFirstAndLastBounces);
  EXPECT_EQ(c.laser.size(), 1u);
  EXPECT_EQ(c.sensor.positions[4], glm::vec3(4, 0, 1));
  EXPECT_FLOAT_EQ(float(c.deltaT), 0.01f);
  const ImageSet image = captureImage(c);
  EXPECT_EQ(image.width, 5u);
  EXPECT_EQ(image.height, 1u);
  EXPECT_EQ(image.layers[1].pixels[3], 13.0f);
  for (const CaptureView& v : captureViews(c)) EXPECT_EQ(v.laser, 0u);
}

Capture exhaustiveCapture() {
  Capture c;
  c.hFormat = CaptureHFormat::T_Li_Si;
  c.dims = {4, 2, 3};
  for (int i = 0; i < 24; ++i) c.H.push_back(0.5f * float(i) - 3.0f);
  c.sensor.shape = {3};
  c.sensor.positions = {{0, 1, 0}, {0.5f, 1, 0}, {1, 1, 0}};
  c.sensor.normals = {{0, -1, 0}, {0, -1, 0}, {0, -1, 0.1f}};
  c.laser.shape = {2};
  c.laser.positions = {{0, 1, 0.5f}, {1, 1, 0.5f}};
  c.laser.normals = {{0, -1, 0}, {0, -1, 0}};
  c.sensorXyz = glm::vec3(0, 2, 0);
  c.laserXyz = glm::vec3(0.1f, 2, 0);
  c.deltaT = 0.0125;
  c.tStart = 1.75;
  c.tAccountsFirstAndLastBounces = true;
  c.sceneInfo = "{generator: vktg}\n";
  return c;
}

TEST_F(NlosCaptureTest, WrittenCapturesReadBackEqual) {
  const Capture exhaustive = exhaustiveCapture();
  writeCaptureTal(m_dir / "exhaustive.hdf5", exhaustive);
  const Capture back = readCapture(m_dir / "exhaustive.hdf5");
  EXPECT_EQ(back.H, exhaustive.H);
  EXPECT_EQ(back.dims, exhaustive.dims);
  EXPECT_EQ(back.sensor, exhaustive.sensor);
  EXPECT_EQ(back.laser, exhaustive.laser);
  EXPECT_EQ(back.sensorXyz, exhaustive.sensorXyz);
  EXPECT_EQ(back.laserXyz, exhaustive.laserXyz);
  EXPECT_EQ(back.deltaT, exhaustive.deltaT);
  EXPECT_EQ(back.tStart, exhaustive.tStart);
  EXPECT_EQ(back.sceneInfo, exhaustive.sceneInfo);
  EXPECT_EQ(back.confocal, exhaustive.confocal);
  EXPECT_EQ(back, exhaustive) << "every field";
  // A confocal grid without the legs and without device positions (tal's None).
  writeTalGrid(m_dir / "grid.hdf5");
  Capture grid = readCapture(m_dir / "grid.hdf5");
  grid.sensorXyz.reset();
  grid.laserXyz.reset();
  grid.sceneInfo = "{source: test}\n";  // without one, tal's reader would find no mapping: "{}" is written
  writeCaptureTal(m_dir / "copy.hdf5", grid);
  const Capture copy = readCapture(m_dir / "copy.hdf5");
  EXPECT_EQ(copy, grid);
  EXPECT_FALSE(copy.sensorXyz.has_value());
  // The same bytes from memory.
  EXPECT_EQ(readCaptureImage(test::readAll(m_dir / "copy.hdf5"), "copy"), grid);
  // With laser axes, the views go sensor by sensor for each laser point.
  const std::vector<CaptureView> views = captureViews(exhaustive);
  ASSERT_EQ(views.size(), 6u);
  EXPECT_EQ(views[4].laser, 1u);
  EXPECT_EQ(views[4].sensor, 1u);
  EXPECT_EQ(captureImage(exhaustive).layers[3].pixels[4], exhaustive.H[3 * 6 + 1 * 3 + 1]);
}

TEST_F(NlosCaptureTest, WritingAnInvalidCaptureLeavesTheExistingFile) {
  test::writePlain(m_dir / "out.hdf5", "previous");
  Capture bad = exhaustiveCapture();
  bad.deltaT = 0;
  expectError([&] { writeCaptureTal(m_dir / "out.hdf5", bad); }, {"out.hdf5", "delta_t", "must be > 0"});
  EXPECT_EQ(test::readAll(m_dir / "out.hdf5"), "previous");
  bad = exhaustiveCapture();
  bad.H[5] = std::numeric_limits<float>::quiet_NaN();
  expectError([&] { writeCaptureTal(m_dir / "out.hdf5", bad); }, {"out.hdf5", "H", "non-finite"});
  bad = exhaustiveCapture();
  bad.confocal = true;
  expectError([&] { writeCaptureTal(m_dir / "out.hdf5", bad); }, {"laser_grid_xyz", "confocal"});
  EXPECT_EQ(test::readAll(m_dir / "out.hdf5"), "previous");
  expectError([&] { writeCaptureTal(m_dir / "missing" / "out.hdf5", exhaustiveCapture()); }, {"does not exist"});
}

// Zaragoza dataset layout, confocal: data (X, Y, bounces, T, colours) column-major, so C order
// (colours, T, bounces, Y, X); grids (3, Y, X). Two bounces of values b + 1000 t + 10 x + y.
void writeZaragoza(const fs::path& path, bool rowMajor, const std::function<void(H5Writer&)>& change = {}) {
  H5Writer w(path);
  const int X = 3, Y = 2, B = 2, T = 4;
  std::vector<float> data, grid, normals;
  auto value = [](int x, int y, int b, int t) { return float(b + 1000 * t + 10 * x + y); };
  if (rowMajor) {
    w.rootString("data order", "row-major");
    for (int x = 0; x < X; ++x)
      for (int y = 0; y < Y; ++y)
        for (int b = 0; b < B; ++b)
          for (int t = 0; t < T; ++t) data.push_back(value(x, y, b, t));
    for (int x = 0; x < X; ++x)
      for (int y = 0; y < Y; ++y) {
        grid.insert(grid.end(), {0.1f * x, 0.0f, 0.2f * y});
        normals.insert(normals.end(), {0, 1, 0});
      }
    w.floats("data", {X, Y, B, T, 1}, data);
    w.floats("cameraGridPositions", {X, Y, 3}, grid);
    w.floats("cameraGridNormals", {X, Y, 3}, normals);
    w.floats("laserGridPositions", {X, Y, 3}, grid);
    w.floats("laserGridNormals", {X, Y, 3}, normals);
  } else {
    for (int t = 0; t < T; ++t)
      for (int b = 0; b < B; ++b)
        for (int y = 0; y < Y; ++y)
          for (int x = 0; x < X; ++x) data.push_back(value(x, y, b, t));
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < Y; ++y)
        for (int x = 0; x < X; ++x) {
          grid.push_back(c == 0 ? 0.1f * x : c == 2 ? 0.2f * y : 0.0f);
          normals.push_back(c == 1 ? 1.0f : 0.0f);
        }
    w.floats("data", {1, T, B, Y, X}, data);
    w.floats("cameraGridPositions", {3, Y, X}, grid);
    w.floats("cameraGridNormals", {3, Y, X}, normals);
    w.floats("laserGridPositions", {3, Y, X}, grid);
    w.floats("laserGridNormals", {3, Y, X}, normals);
  }
  w.doubles("cameraPosition", {3, 1}, {0, -1, 0.5});
  w.doubles("laserPosition", {3, 1}, {0.2, -1, 0.5});
  w.doubles("deltaT", {1, 1}, {0.001});
  w.doubles("t0", {1, 1}, {0.0});
  w.doubles("hiddenVolumePosition", {3, 1}, {0, 0.5, 0});  // read by nobody here
  if (change) change(w);
}

TEST_F(NlosCaptureTest, ZaragozaDatasetFilesReadInEitherDataOrder) {
  for (bool rowMajor : {false, true}) {
    const fs::path path = m_dir / (rowMajor ? "row.hdf5" : "column.hdf5");
    writeZaragoza(path, rowMajor);
    const Capture c = readCapture(path);
    EXPECT_EQ(c.hFormat, CaptureHFormat::T_Sx_Sy);
    ASSERT_EQ(c.dims, (std::vector<uint32_t>{4, 3, 2})) << "(T, Sx, Sy)";
    // H[t, x, y] is the sum over the two bounces: 2 (1000 t + 10 x + y) + 0 + 1.
    EXPECT_EQ(c.H[(3 * 3 + 2) * 2 + 1], 2.0f * (3000 + 20 + 1) + 1) << (rowMajor ? "row-major" : "column-major");
    EXPECT_EQ(c.sensor.positions[2 * 2 + 1], glm::vec3(0.2f, 0.0f, 0.2f)) << "grid point (2, 1)";
    EXPECT_EQ(c.sensor.normals[0], glm::vec3(0, 1, 0));
    EXPECT_TRUE(c.confocal);
    EXPECT_TRUE(c.tAccountsFirstAndLastBounces);
    EXPECT_EQ(*c.sensorXyz, glm::vec3(0, -1, 0.5f));
    EXPECT_EQ(*c.laserXyz, glm::vec3(0.2f, -1, 0.5f));
    EXPECT_EQ(c.deltaT, 0.001);
  }
}

TEST_F(NlosCaptureTest, MissingAndUnreadableFilesAreErrors) {
  expectError([&] { readCapture(m_dir / "none.hdf5"); }, {"none.hdf5", "file not found"});
  test::writePlain(m_dir / "text.hdf5", "not an HDF5 file at all");
  expectError([&] { readCapture(m_dir / "text.hdf5"); }, {"text.hdf5", "not an HDF5 file"});
  expectError([&] { readCaptureImage("garbage", "memory"); }, {"memory", "not an HDF5 file"});
  { H5Writer w(m_dir / "empty.hdf5"); }
  expectError([&] { readCapture(m_dir / "empty.hdf5"); }, {"empty.hdf5", "neither a tal capture", "Zaragoza"});
}

// Each change to the good tal file and the error it must give.
struct TalCase {
  const char* what;
  std::function<void(H5Writer&)> change;
  std::vector<std::string> message;
};

TEST_F(NlosCaptureTest, BadTalFilesNameTheDatasetAndTheProblem) {
  const std::vector<TalCase> cases = {
      {"H missing", [](H5Writer& w) { H5Ldelete(w.id(), "H", H5P_DEFAULT); }, {"H: missing dataset"}},
      {"H of the wrong rank",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         w.floats("H", {24}, std::vector<float>(24, 1.0f));
       },
       {"H: shape (24,) has rank 1", "T_Sx_Sy"}},
      {"grid not matching H",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         w.floats("H", {3, 2, 4}, std::vector<float>(24, 1.0f));
       },
       {"sensor_grid_xyz", "does not match H's sensor axes (2, 4)"}},
      {"normals of another shape",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "sensor_grid_normals", H5P_DEFAULT);
         w.floats("sensor_grid_normals", {8, 3}, std::vector<float>(24, 1.0f));
       },
       {"sensor_grid_normals", "differs from sensor_grid_xyz's (4, 2, 3)"}},
      {"grid format disagreeing with the grid",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "laser_grid_format", H5P_DEFAULT);
         w.talEnum("laser_grid_format", 1);
       },
       {"laser_grid_xyz", "is not (N, 3)"}},
      {"a non-finite value",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         std::vector<float> H(24, 1.0f);
         H[13] = std::numeric_limits<float>::infinity();
         w.floats("H", {3, 4, 2}, H);
       },
       {"H: non-finite value inf at index (1, 2, 1)"}},
      {"a double beyond float range",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "sensor_grid_xyz", H5P_DEFAULT);
         std::vector<double> grid(24, 0.0);
         grid[4] = 1e300;
         w.doubles("sensor_grid_xyz", {4, 2, 3}, grid);
       },
       {"sensor_grid_xyz: value 1e+300 at index (0, 1, 1) is outside the range of 32-bit floats"}},
      {"delta_t of 0",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "delta_t", H5P_DEFAULT);
         w.doubles("delta_t", {}, {0.0});
       },
       {"delta_t: must be > 0"}},
      {"delta_t of two numbers",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "delta_t", H5P_DEFAULT);
         w.doubles("delta_t", {2}, {0.1, 0.2});
       },
       {"delta_t: expected one number, got shape (2,)"}},
      {"an unknown H_format",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H_format", H5P_DEFAULT);
         w.int64("H_format", 7);
       },
       {"H_format: unknown H_format 7"}},
      {"frequency-domain data",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H_format", H5P_DEFAULT);
         w.talEnum("H_format", 10);
       },
       {"H_format: 10 (F_Sx_Sy) is frequency-domain data"}},
      {"H of strings",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         const hid_t type = H5Tcopy(H5T_C_S1);
         H5Tset_size(type, 4);
         const hsize_t dims[3] = {3, 4, 2};
         const hid_t space = H5Screate_simple(3, dims, nullptr);
         H5Dclose(H5Dcreate2(w.id(), "H", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
         H5Sclose(space);
         H5Tclose(type);
       },
       {"H: wrong type: expected numbers, got a string"}},
      {"a boolean that is not one",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "t_accounts_first_and_last_bounces", H5P_DEFAULT);
         w.int64("t_accounts_first_and_last_bounces", 2);
       },
       {"t_accounts_first_and_last_bounces: 2 is not a boolean"}},
      {"legs counted without the devices",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "t_accounts_first_and_last_bounces", H5P_DEFAULT);
         w.boolean("t_accounts_first_and_last_bounces", true);
         H5Ldelete(w.id(), "laser_xyz", H5P_DEFAULT);
       },
       {"laser_xyz: missing or empty, but t_accounts_first_and_last_bounces is true"}},
      {"a group where a dataset belongs",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "t_start", H5P_DEFAULT);
         H5Gclose(H5Gcreate2(w.id(), "t_start", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
       },
       {"t_start: not a dataset"}},
      {"an external link",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         H5Lcreate_external("other.hdf5", "H", w.id(), "H", H5P_DEFAULT, H5P_DEFAULT);
       },
       {"H: a soft or external link"}},
      {"a dataset declaring more values than vktg reads (never written, so nothing to read)",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "H", H5P_DEFAULT);
         w.floats("H", {1u << 20, 1u << 10, 1u << 10}, {});
       },
       {"H: shape (1048576, 1024, 1024) holds more than 268435456 values"}},
  };
  for (const TalCase& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path path = m_dir / "bad.hdf5";
    writeTalGrid(path, c.change);
    std::vector<std::string> parts = c.message;
    parts.push_back(path.string() + ": ");
    expectError([&] { readCapture(path); }, parts);
  }
}

TEST_F(NlosCaptureTest, BadZaragozaFilesNameTheDatasetAndTheProblem) {
  const std::vector<TalCase> cases = {
      {"data of rank 4",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "data", H5P_DEFAULT);
         w.floats("data", {4, 2, 2, 3}, std::vector<float>(48, 1.0f));
       },
       {"data: shape (4, 2, 2, 3) has rank 4"}},
      {"grid not matching data",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "cameraGridPositions", H5P_DEFAULT);
         w.floats("cameraGridPositions", {3, 3, 2}, std::vector<float>(18, 0.0f));
       },
       {"cameraGridPositions: its grid (X, Y) = (2, 3) does not match data's sensor axes (X, Y) = (3, 2)"}},
      {"an unknown data order",
       [](H5Writer& w) { w.rootString("data order", "diagonal"); },
       {"attribute \"data order\": \"diagonal\" is neither"}},
      {"laserPosition missing", [](H5Writer& w) { H5Ldelete(w.id(), "laserPosition", H5P_DEFAULT); }, {"laserPosition: missing dataset"}},
      {"deltaT negative",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "deltaT", H5P_DEFAULT);
         w.doubles("deltaT", {1, 1}, {-0.1});
       },
       {"deltaT: must be > 0"}},
      {"a NaN in data",
       [](H5Writer& w) {
         H5Ldelete(w.id(), "data", H5P_DEFAULT);
         std::vector<float> data(48, 1.0f);
         data[7] = std::numeric_limits<float>::quiet_NaN();
         w.floats("data", {1, 4, 2, 2, 3}, data);
       },
       {"data: value nan at index (0, 0, 1, 0, 1) is not finite"}},
  };
  for (const TalCase& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path path = m_dir / "bad.hdf5";
    writeZaragoza(path, false, c.change);
    std::vector<std::string> parts = c.message;
    parts.push_back(path.string() + ": ");
    expectError([&] { readCapture(path); }, parts);
  }
}

}  // namespace
}  // namespace vktg
