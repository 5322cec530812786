// Fuzz target: the NLOS capture reader (readCapture, src/io/nlos_capture.h), structurally. HDF5's
// own parser is not robust against arbitrary bytes (and is not vktg's to fix), so the input is not
// the file: it decodes into a description of one (root datasets named from the tal and Zaragoza
// vocabularies, with their ranks, shapes, types, storage and values, groups and links in their
// place, the root's "data order" attribute), which this target writes with the HDF5 library into a
// file in memory and hands to the reader. Every input must end in a Capture, whose image and views
// then derive, or in one vktg::Error.
// vktg-fuzz-links: vktg_io
// vktg-fuzz-seeds: fuzz/seeds/capture/*.bin
#include <hdf5.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "io/nlos_capture.h"

namespace {

// Datasets that write more values than this come from the input's bytes (a dataset larger than
// the reader's limit is only declared, so that the reader must refuse it by its shape).
constexpr uint64_t kMaxWrittenValues = 4096;
constexpr uint64_t kReaderLimit = uint64_t(1) << 28;

const char* const kNames[] = {
    "H", "H_format", "sensor_xyz", "sensor_grid_xyz", "sensor_grid_normals", "sensor_grid_format", "laser_xyz",
    "laser_grid_xyz", "laser_grid_normals", "laser_grid_format", "delta_t", "t_start",
    "t_accounts_first_and_last_bounces", "scene_info", "volume_format", "data", "deltaT", "t0", "cameraGridPositions",
    "cameraGridNormals", "cameraPosition", "laserGridPositions", "laserGridNormals", "laserPosition", "isConfocal", "x"};
constexpr size_t kNameCount = sizeof(kNames) / sizeof(kNames[0]);

// Numbers that matter to the reader: the values valid captures hold, and the edges of float and
// integer ranges.
const double kNumbers[32] = {0,     1,      -1,    0.5,   2,    0.05,  1.6,  0.25,  3,     10,    100,
                             1e-3,  -0.5,   4,     7,     0.1,  1e38,  -1e38, 3.5e38, 1e300, -1e300, NAN,
                             INFINITY, -INFINITY, 1e-40, -0.0, 1e-310, 65536, 2147483648.0, -2147483648.0, 255, 13};

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : m_data(data), m_size(size) {}
  bool empty() const { return m_at >= m_size; }
  uint8_t next() { return m_at < m_size ? m_data[m_at++] : 0; }

 private:
  const uint8_t* m_data;
  size_t m_size, m_at = 0;
};

struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

// The file type of kind k (the low four bits of a dataset's kind byte), or -1 for the kinds that
// are not datasets of numbers.
hid_t makeType(uint8_t kind) {
  switch (kind) {
    case 0: return H5Tcopy(H5T_IEEE_F32LE);
    case 1: return H5Tcopy(H5T_IEEE_F64BE);
    case 2: return H5Tcopy(H5T_STD_I32LE);
    case 3: return H5Tcopy(H5T_STD_I64BE);
    case 4: return H5Tcopy(H5T_STD_U8LE);
    case 5: return H5Tcopy(H5T_STD_I8LE);
    case 6: {  // tal's enums (h5py.enum_dtype, int32)
      const hid_t t = H5Tenum_create(H5T_NATIVE_INT32);
      const char* names[] = {"UNKNOWN", "T_Sx_Sy", "T_Lx_Ly_Sx_Sy", "T_Si", "T_Li_Si", "F_Sx_Sy"};
      const int32_t values[] = {0, 1, 2, 3, 4, 10};
      for (int i = 0; i < 6; ++i) H5Tenum_insert(t, names[i], &values[i]);
      return t;
    }
    case 7: {  // h5py's bool
      const hid_t t = H5Tenum_create(H5T_NATIVE_INT8);
      const int8_t no = 0, yes = 1;
      H5Tenum_insert(t, "FALSE", &no);
      H5Tenum_insert(t, "TRUE", &yes);
      return t;
    }
    case 8: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, 8);
      return t;
    }
    case 9: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, H5T_VARIABLE);
      H5Tset_cset(t, H5T_CSET_UTF8);
      return t;
    }
    case 10: {  // complex numbers as h5py writes them
      const hid_t t = H5Tcreate(H5T_COMPOUND, 8);
      H5Tinsert(t, "r", 0, H5T_NATIVE_FLOAT);
      H5Tinsert(t, "i", 4, H5T_NATIVE_FLOAT);
      return t;
    }
    case 11: {  // a half float
      const hid_t t = H5Tcopy(H5T_IEEE_F32LE);
      H5Tset_fields(t, 15, 10, 5, 0, 10);
      H5Tset_precision(t, 16);
      H5Tset_size(t, 2);
      H5Tset_ebias(t, 15);
      return t;
    }
    default: return -1;
  }
}

// Values for `count` elements of kind `kind` in the memory layout H5Dwrite gets with `memoryType`.
std::vector<unsigned char> makeValues(uint8_t kind, uint64_t count, Bytes& in, hid_t& memoryType, hid_t fileType,
                                      std::vector<std::string>& strings, std::vector<const char*>& pointers) {
  std::vector<unsigned char> out;
  auto append = [&](const void* p, size_t n) { out.insert(out.end(), (const unsigned char*)p, (const unsigned char*)p + n); };
  for (uint64_t i = 0; i < count; ++i) {
    const uint8_t b = in.next();
    switch (kind) {
      case 0: case 1: case 10: case 11: {
        const double v = kNumbers[b & 31];
        append(&v, sizeof v);
        if (kind == 10) append(&v, sizeof v);
        break;
      }
      case 2: case 3: case 4: case 5: {
        int64_t v = int8_t(b);
        if (b >= 0xF8) v = b == 0xF8 ? std::numeric_limits<int64_t>::min() : b == 0xF9 ? std::numeric_limits<int64_t>::max()
                                                                          : int64_t(1) << (b - 0xF8 + 28);
        append(&v, sizeof v);
        break;
      }
      case 6: { const int32_t v = int8_t(b); append(&v, sizeof v); break; }
      case 7: { const int8_t v = int8_t(b & 3); append(&v, sizeof v); break; }
      default: {  // strings: up to 8 characters of the input
        std::string s;
        for (uint8_t n = b & 7; n > 0; --n) s.push_back(char(in.next()));
        strings.push_back(s);
        break;
      }
    }
  }
  switch (kind) {
    case 0: case 1: case 11: memoryType = H5Tcopy(H5T_NATIVE_DOUBLE); break;
    case 10: {
      memoryType = H5Tcreate(H5T_COMPOUND, 16);
      H5Tinsert(memoryType, "r", 0, H5T_NATIVE_DOUBLE);
      H5Tinsert(memoryType, "i", 8, H5T_NATIVE_DOUBLE);
      break;
    }
    case 2: case 3: case 4: case 5: memoryType = H5Tcopy(H5T_NATIVE_INT64); break;
    case 6: case 7: memoryType = H5Tcopy(fileType); break;
    case 8: {
      memoryType = H5Tcopy(fileType);
      out.clear();
      for (const std::string& s : strings) {
        char fixed[8] = {};
        std::memcpy(fixed, s.data(), std::min<size_t>(s.size(), 8));
        append(fixed, 8);
      }
      break;
    }
    default: {
      memoryType = H5Tcopy(fileType);
      for (const std::string& s : strings) pointers.push_back(s.c_str());
      out.clear();
      append(pointers.data(), pointers.size() * sizeof(const char*));
      break;
    }
  }
  return out;
}

// One root entry from the input: a dataset, or a group or link in a dataset's place.
void writeEntry(hid_t file, Bytes& in) {
  const char* name = kNames[in.next() % kNameCount];
  const uint8_t kindByte = in.next();
  const uint8_t kind = kindByte & 15;
  if (H5Lexists(file, name, H5P_DEFAULT) > 0) return;
  if (kind == 12) {
    H5Gclose(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    return;
  }
  if (kind == 13) {
    H5Lcreate_soft(kNames[in.next() % kNameCount], file, name, H5P_DEFAULT, H5P_DEFAULT);
    return;
  }
  if (kind == 14) {
    H5Lcreate_external("elsewhere.h5", "H", file, name, H5P_DEFAULT, H5P_DEFAULT);
    return;
  }
  const bool chunked = kindByte & 16, compressed = kindByte & 32, null = kindByte & 64, declaredOnly = kindByte & 128;
  const int rank = in.next() % 8;
  std::vector<hsize_t> dims(static_cast<size_t>(rank));
  bool huge = false;
  double total = 1;
  for (hsize_t& d : dims) {
    const uint8_t b = in.next();
    d = b >= 0xF0 ? hsize_t(1) << (16 + (b & 15)) : b % 17;
    total *= double(d);
  }
  huge = total > double(kReaderLimit);
  if (!huge && total > double(kMaxWrittenValues)) return;  // neither small nor refused by its shape
  Handle type{makeType(kind), H5Tclose};
  if (type.id < 0) return;
  Handle space{null ? H5Screate(H5S_NULL) : rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims.data(), nullptr),
               H5Sclose};
  Handle create{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  if (chunked && rank > 0 && !null) {
    std::vector<hsize_t> chunk(dims.size());
    for (size_t a = 0; a < dims.size(); ++a) chunk[a] = std::max<hsize_t>(1, std::min<hsize_t>(dims[a], 1 + in.next() % 4));
    H5Pset_chunk(create.id, rank, chunk.data());
    if (compressed) H5Pset_deflate(create.id, 1);
  }
  Handle dataset{H5Dcreate2(file, name, type.id, space.id, H5P_DEFAULT, create.id, H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0 || null || huge || declaredOnly) return;
  std::vector<std::string> strings;
  std::vector<const char*> pointers;
  hid_t memory = -1;
  const std::vector<unsigned char> values = makeValues(kind, uint64_t(total), in, memory, type.id, strings, pointers);
  Handle memoryType{memory, H5Tclose};
  if (memoryType.id >= 0 && !values.empty())
    H5Dwrite(dataset.id, memoryType.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
}

void writeDataOrder(hid_t file, uint8_t flags) {
  if (!(flags & 1)) return;
  const char* values[] = {"row-major", "column-major", "diagonal", ""};
  const std::string value = values[(flags >> 1) & 3];
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  if (flags & 8) {  // not a string
    const int32_t v = 1;
    Handle a{H5Acreate2(file, "data order", H5T_STD_I32LE, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (a.id >= 0) H5Awrite(a.id, H5T_NATIVE_INT32, &v);
    return;
  }
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, std::max<size_t>(1, value.size()));
  Handle a{H5Acreate2(file, "data order", type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (a.id >= 0) H5Awrite(a.id, type.id, value.c_str());
}

// The file the input describes, as the bytes of an HDF5 file.
std::string buildFile(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_fapl_core(access.id, 1 << 16, 0);
  std::string image;
  {
    Handle file{H5Fcreate("fuzz-capture.h5", H5F_ACC_TRUNC, H5P_DEFAULT, access.id), H5Fclose};
    if (file.id < 0) std::abort();
    writeDataOrder(file.id, in.next());
    for (int entries = 0; entries < 32 && !in.empty(); ++entries) writeEntry(file.id, in);
    H5Fflush(file.id, H5F_SCOPE_GLOBAL);
    const ssize_t n = H5Fget_file_image(file.id, nullptr, 0);
    if (n <= 0) std::abort();
    image.resize(size_t(n));
    if (H5Fget_file_image(file.id, image.data(), size_t(n)) != n) std::abort();
  }
  return image;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string image = buildFile(data, size);
  vktg::fuzz::expectOnlyVktgErrors([&] {
    const vktg::Capture capture = vktg::readCaptureImage(image, "fuzz.h5");
    vktg::validateCapture(capture, "fuzz.h5");
    const vktg::ImageSet picture = vktg::captureImage(capture);
    const std::vector<vktg::CaptureView> views = vktg::captureViews(capture);
    if (views.size() != size_t(picture.width) * picture.height) std::abort();
    for (const vktg::CaptureView& v : views)
      if (v.sensor >= capture.sensor.size() || v.laser >= capture.laser.size()) std::abort();
  });
  return 0;
}
