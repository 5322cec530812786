#include "io/hdf5_file.h"

#include <unistd.h>

#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg::io::hdf5 {
namespace {

namespace fs = std::filesystem;

// Values per block of a streamed read (8 MiB of doubles).
constexpr uint64_t kBlockValues = uint64_t(1) << 20;
// A chunk is read whole whenever any of it is: a larger one would make each block read cost that.
constexpr uint64_t kMaxChunkBytes = uint64_t(64) << 20;
// Strings (scene_info, attributes) are metadata, never this long.
constexpr size_t kMaxStringBytes = size_t(1) << 20;

std::string className(H5T_class_t c) {
  switch (c) {
    case H5T_INTEGER: return "integers";
    case H5T_FLOAT: return "floats";
    case H5T_STRING: return "a string";
    case H5T_ENUM: return "an enumeration";
    case H5T_COMPOUND: return "a compound type (complex numbers or records)";
    case H5T_ARRAY: return "an array type";
    case H5T_VLEN: return "variable-length sequences";
    case H5T_BITFIELD: return "a bit field";
    case H5T_OPAQUE: return "opaque data";
    case H5T_REFERENCE: return "references";
    case H5T_TIME: return "time values";
    default: return "an unknown type";
  }
}

// "(i, j, k)" for flat index `flat` of a C-order array of shape `dims`.
std::string describeIndex(uint64_t flat, const std::vector<uint64_t>& dims) {
  std::vector<uint64_t> index(dims.size());
  for (size_t a = dims.size(); a-- > 0;) {
    index[a] = flat % dims[a];
    flat /= dims[a];
  }
  return describeDims(index);
}

Handle property(hid_t cls) { return Handle(H5Pcreate(cls), H5Pclose); }

// A string value read with `read(memoryType, buffer)` from an object of string type `type`.
template <typename Read>
std::optional<std::string> readStringValue(hid_t type, const Read& read) {
  if (H5Tis_variable_str(type) > 0) {
    Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
    // HDF5 converts no string between character sets: read in the file's (ASCII or UTF-8).
    if (!memory.valid() || H5Tset_size(memory.get(), H5T_VARIABLE) < 0 || H5Tset_cset(memory.get(), H5Tget_cset(type)) < 0)
      return std::nullopt;
    char* text = nullptr;
    if (read(memory.get(), &text) < 0) return std::nullopt;
    std::string out = text ? std::string(text, strnlen(text, kMaxStringBytes)) : std::string();
    if (text) H5free_memory(text);
    return out;
  }
  const size_t size = H5Tget_size(type);
  if (size == 0 || size > kMaxStringBytes) return std::nullopt;
  Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!memory.valid() || H5Tset_size(memory.get(), size) < 0 || H5Tset_cset(memory.get(), H5Tget_cset(type)) < 0)
    return std::nullopt;
  std::vector<char> buffer(size + 1, '\0');
  if (read(memory.get(), buffer.data()) < 0) return std::nullopt;
  std::string out(buffer.data(), strnlen(buffer.data(), size));
  // Fixed-length strings may be padded with spaces (MATLAB's) or NULs.
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

}  // namespace

void quietLibrary() {
  static std::once_flag once;
  std::call_once(once, [] {
    H5open();
    // Filters come from the library itself (deflate, shuffle...); a file cannot make it load code.
    H5PLset_loading_state(0);
  });
  // Per thread in a thread-safe HDF5 build, so set on every entry.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

File openFile(const std::string& path) {
  quietLibrary();
  std::error_code error;
  if (!fs::exists(path, error)) fail(path, "", "cannot read: file not found");
  if (!fs::is_regular_file(path, error)) fail(path, "", "cannot read: not a regular file");
  if (!std::ifstream(path, std::ios::binary)) fail(path, "", "cannot read file (permission denied or I/O error)");
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
  if (isHdf5 <= 0) fail(path, "", "not an HDF5 file (no HDF5 signature)");
  Handle access = property(H5P_FILE_ACCESS);
#if H5_VERSION_GE(1, 10, 7)
  // Reading needs no lock, and file systems without locks (some network mounts) refuse one.
  H5Pset_file_locking(access.get(), false, true);
#endif
  File file{Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose), path};
  if (!file.handle.valid()) fail(path, "", "cannot open as HDF5 (a damaged or truncated file)");
  return file;
}

File openImage(const std::string& bytes, const std::string& name) {
  quietLibrary();
  static std::atomic<uint64_t> counter{0};
  Handle access = property(H5P_FILE_ACCESS);
  if (!access.valid() || H5Pset_fapl_core(access.get(), 1 << 16, 0) < 0 ||
      H5Pset_file_image(access.get(), const_cast<char*>(bytes.data()), bytes.size()) < 0)
    fail(name, "", "cannot open the file image in memory");
  // The core driver names files only to tell open ones apart.
  const std::string internal = "vktg-capture-image-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  File file{Handle(H5Fopen(internal.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose), name};
  if (!file.handle.valid()) fail(name, "", "not an HDF5 file (no HDF5 signature, or a damaged file)");
  return file;
}

void failAt(const File& file, const std::string& dataset, const std::string& problem) { fail(file.name, dataset, problem); }

uint64_t Dataset::count() const {
  if (null) return 0;
  uint64_t n = 1;
  for (uint64_t d : dims) n *= d;  // bounded by kMaxValues when opened
  return n;
}

std::string describeDims(const std::vector<uint64_t>& dims) {
  std::string s = "(";
  for (size_t a = 0; a < dims.size(); ++a) s += (a ? ", " : "") + std::to_string(dims[a]);
  return s + (dims.size() == 1 ? ",)" : ")");
}

bool hasLink(const File& file, const std::string& name) { return H5Lexists(file.handle.get(), name.c_str(), H5P_DEFAULT) > 0; }

std::optional<Dataset> openOptional(const File& file, const std::string& name) {
  if (!hasLink(file, name)) return std::nullopt;
  return openDataset(file, name);
}

Dataset openDataset(const File& file, const std::string& name) {
  const hid_t root = file.handle.get();
  if (!hasLink(file, name)) failAt(file, name, "missing dataset");
  H5L_info_t link;
  if (H5Lget_info(root, name.c_str(), &link, H5P_DEFAULT) < 0) failAt(file, name, "cannot read its link");
  if (link.type != H5L_TYPE_HARD)
    failAt(file, name, "a soft or external link: vktg reads only datasets stored in the file itself");
  Dataset d;
  d.name = name;
  d.handle = Handle(H5Dopen2(root, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.handle.valid()) failAt(file, name, "not a dataset (a group or another kind of object)");
  Handle space(H5Dget_space(d.handle.get()), H5Sclose);
  const H5S_class_t kind = space.valid() ? H5Sget_simple_extent_type(space.get()) : H5S_NO_CLASS;
  if (kind == H5S_NULL) {
    d.null = true;
  } else if (kind == H5S_SIMPLE) {
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 0 || rank > H5S_MAX_RANK) failAt(file, name, "cannot read its shape");
    std::vector<hsize_t> dims(static_cast<size_t>(rank));
    if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0) failAt(file, name, "cannot read its shape");
    d.dims.assign(dims.begin(), dims.end());
    uint64_t n = 1;
    for (uint64_t dim : d.dims) {
      if (dim == 0) {
        n = 0;
        break;
      }
      if (n > kMaxValues / dim) {  // before the product could overflow
        n = kMaxValues + 1;
        break;
      }
      n *= dim;
    }
    if (n > kMaxValues)
      failAt(file, name, "shape " + describeDims(d.dims) + " holds more than " + std::to_string(kMaxValues) +
                             " values, the most vktg reads from one dataset");
  } else if (kind != H5S_SCALAR) {
    failAt(file, name, "cannot read its shape");
  }
  Handle type(H5Dget_type(d.handle.get()), H5Tclose);
  if (!type.valid()) failAt(file, name, "cannot read its type");
  d.typeClass = H5Tget_class(type.get());
  Handle create(H5Dget_create_plist(d.handle.get()), H5Pclose);
  if (!create.valid()) failAt(file, name, "cannot read its storage properties");
  const H5D_layout_t layout = H5Pget_layout(create.get());
  if (layout == H5D_VIRTUAL) failAt(file, name, "a virtual dataset: its values live in other files, which vktg does not open");
  if (H5Pget_external_count(create.get()) > 0)
    failAt(file, name, "stored in external files, which vktg does not open");
  if (layout == H5D_CHUNKED && !d.dims.empty()) {
    std::vector<hsize_t> chunk(d.dims.size());
    if (H5Pget_chunk(create.get(), int(chunk.size()), chunk.data()) != int(chunk.size()))
      failAt(file, name, "cannot read its chunk shape");
    double bytes = double(H5Tget_size(type.get()));
    for (hsize_t c : chunk) bytes *= double(c);
    if (bytes > double(kMaxChunkBytes))
      failAt(file, name, "chunks of " + describeDims(std::vector<uint64_t>(chunk.begin(), chunk.end())) + " (" +
                             formatNumber(bytes) + " bytes); vktg reads chunks of at most 64 MiB");
  }
  return d;
}

void readBlocks(const File& file, const Dataset& dataset,
                const std::function<void(uint64_t first, const double* values, size_t count)>& visit) {
  const std::string& name = dataset.name;
  if (dataset.typeClass != H5T_INTEGER && dataset.typeClass != H5T_FLOAT)
    failAt(file, name, "wrong type: expected numbers, got " + className(dataset.typeClass));
  if (dataset.null) failAt(file, name, "empty (a dataset without values)");
  const uint64_t total = dataset.count();
  if (total == 0) failAt(file, name, "empty: shape " + describeDims(dataset.dims));
  const hid_t handle = dataset.handle.get();
  const char* unreadable = "cannot read its values (damaged data, or a filter this HDF5 library lacks)";
  if (dataset.dims.empty()) {
    double value = 0;
    if (H5Dread(handle, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0) failAt(file, name, unreadable);
    visit(0, &value, 1);
    return;
  }
  // Blocks are hyperslabs: one index on each axis before `split`, a run of rows along it, every
  // index after it; so each is a contiguous run of the C-order values.
  const std::vector<uint64_t>& dims = dataset.dims;
  const size_t rank = dims.size();
  size_t split = rank - 1;
  uint64_t inner = 1;  // values per index along `split`
  while (split > 0 && inner * dims[split] <= kBlockValues) inner *= dims[split--];
  const uint64_t rows = std::max<uint64_t>(1, kBlockValues / inner);
  Handle fileSpace(H5Dget_space(handle), H5Sclose);
  if (!fileSpace.valid()) failAt(file, name, unreadable);
  std::vector<double> buffer(size_t(std::min<uint64_t>(total, rows * inner)));
  std::vector<hsize_t> start(rank, 0), count(rank, 1);
  for (size_t a = split + 1; a < rank; ++a) count[a] = dims[a];
  uint64_t first = 0;
  while (first < total) {
    const uint64_t n = std::min<uint64_t>(rows, dims[split] - start[split]);
    count[split] = n;
    const hsize_t values = n * inner;
    Handle memory(H5Screate_simple(1, &values, nullptr), H5Sclose);
    if (!memory.valid() ||
        H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) < 0 ||
        H5Dread(handle, H5T_NATIVE_DOUBLE, memory.get(), fileSpace.get(), H5P_DEFAULT, buffer.data()) < 0)
      failAt(file, name, unreadable);
    visit(first, buffer.data(), size_t(values));
    first += values;
    // The next block: further along `split`, or the next index of the axes before it.
    start[split] += n;
    for (size_t a = split; a > 0 && start[a] == dims[a]; --a) {
      start[a] = 0;
      ++start[a - 1];
    }
  }
}

std::vector<float> readFloats(const File& file, const Dataset& dataset) {
  std::vector<float> out;
  out.reserve(size_t(dataset.count()));
  readBlocks(file, dataset, [&](uint64_t first, const double* values, size_t count) {
    for (size_t i = 0; i < count; ++i) {
      const double v = values[i];
      if (!std::isfinite(v))
        failAt(file, dataset.name, "non-finite value " + formatNumber(v) + " at index " + describeIndex(first + i, dataset.dims));
      if (std::abs(v) > double(FLT_MAX))
        failAt(file, dataset.name, "value " + formatNumber(v) + " at index " + describeIndex(first + i, dataset.dims) +
                                       " is outside the range of 32-bit floats");
      out.push_back(float(v));
    }
  });
  return out;
}

double readScalar(const File& file, const Dataset& dataset) {
  if (!dataset.null && dataset.count() != 1)
    failAt(file, dataset.name, "expected one number, got shape " + describeDims(dataset.dims));
  double out = 0;
  readBlocks(file, dataset, [&](uint64_t, const double* values, size_t) { out = values[0]; });
  if (!std::isfinite(out)) failAt(file, dataset.name, "non-finite value " + formatNumber(out));
  return out;
}

int64_t readInteger(const File& file, const Dataset& dataset) {
  const std::string& name = dataset.name;
  if (dataset.typeClass != H5T_INTEGER && dataset.typeClass != H5T_ENUM)
    failAt(file, name, "wrong type: expected an integer or an enumeration, got " + className(dataset.typeClass));
  if (dataset.null) failAt(file, name, "empty (a dataset without values)");
  if (dataset.count() != 1) failAt(file, name, "expected one value, got shape " + describeDims(dataset.dims));
  const hid_t handle = dataset.handle.get();
  const char* unreadable = "cannot read its value";
  if (dataset.typeClass == H5T_INTEGER) {
    int64_t value = 0;
    if (H5Dread(handle, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0) failAt(file, name, unreadable);
    return value;
  }
  // HDF5 converts an enumeration only to another enumeration: read it in its own (native) type and
  // take the bits as its base integer.
  Handle type(H5Dget_type(handle), H5Tclose);
  Handle native(type.valid() ? H5Tget_native_type(type.get(), H5T_DIR_ASCEND) : H5I_INVALID_HID, H5Tclose);
  Handle base(native.valid() ? H5Tget_super(native.get()) : H5I_INVALID_HID, H5Tclose);
  if (!base.valid()) failAt(file, name, unreadable);
  const size_t size = H5Tget_size(native.get());
  if (size != 1 && size != 2 && size != 4 && size != 8) failAt(file, name, "an enumeration of " + std::to_string(size) + "-byte integers");
  alignas(8) unsigned char bytes[8] = {};
  if (H5Dread(handle, native.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes) < 0) failAt(file, name, unreadable);
  const bool isSigned = H5Tget_sign(base.get()) == H5T_SGN_2;
  switch (size) {
    case 1: { int8_t v; std::memcpy(&v, bytes, 1); return isSigned ? int64_t(v) : int64_t(uint8_t(v)); }
    case 2: { int16_t v; std::memcpy(&v, bytes, 2); return isSigned ? int64_t(v) : int64_t(uint16_t(v)); }
    case 4: { int32_t v; std::memcpy(&v, bytes, 4); return isSigned ? int64_t(v) : int64_t(uint32_t(v)); }
    default: { int64_t v; std::memcpy(&v, bytes, 8); return v; }
  }
}

std::optional<std::string> readRootStringAttribute(const File& file, const std::string& name) {
  const hid_t root = file.handle.get();
  if (H5Aexists(root, name.c_str()) <= 0) return std::nullopt;
  const std::string where = "attribute \"" + name + "\"";
  Handle attribute(H5Aopen(root, name.c_str(), H5P_DEFAULT), H5Aclose);
  Handle type(attribute.valid() ? H5Aget_type(attribute.get()) : H5I_INVALID_HID, H5Tclose);
  Handle space(attribute.valid() ? H5Aget_space(attribute.get()) : H5I_INVALID_HID, H5Sclose);
  if (!type.valid() || !space.valid()) failAt(file, where, "cannot read it");
  if (H5Tget_class(type.get()) != H5T_STRING)
    failAt(file, where, "wrong type: expected a string, got " + className(H5Tget_class(type.get())));
  if (H5Sget_simple_extent_npoints(space.get()) != 1) failAt(file, where, "expected one string");
  const std::optional<std::string> value =
      readStringValue(type.get(), [&](hid_t memory, void* buffer) { return H5Aread(attribute.get(), memory, buffer); });
  if (!value) failAt(file, where, "cannot read its string");
  return value;
}

std::optional<std::string> readString(const File&, const Dataset& dataset) {
  if (dataset.typeClass != H5T_STRING || dataset.null || dataset.count() != 1) return std::nullopt;
  Handle type(H5Dget_type(dataset.handle.get()), H5Tclose);
  if (!type.valid()) return std::nullopt;
  return readStringValue(type.get(), [&](hid_t memory, void* buffer) {
    return H5Dread(dataset.handle.get(), memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
  });
}

// ---- writing ----

Writer::Writer(std::string name) : m_name(std::move(name)) {
  quietLibrary();
  static std::atomic<uint64_t> counter{0};
  Handle access = property(H5P_FILE_ACCESS);
  if (!access.valid() || H5Pset_fapl_core(access.get(), size_t(1) << 20, 0) < 0) failWrite("", "cannot set up an HDF5 file in memory");
  const std::string internal = "vktg-capture-write-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  m_file = Handle(H5Fcreate(internal.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
  if (!m_file.valid()) failWrite("", "cannot create an HDF5 file in memory");
}

void Writer::failWrite(const std::string& dataset, const std::string& problem) const {
  fail(m_name, dataset, "cannot write: " + problem);
}

namespace {

Handle spaceOf(const std::vector<uint64_t>& dims) {
  if (dims.empty()) return Handle(H5Screate(H5S_SCALAR), H5Sclose);
  const std::vector<hsize_t> extent(dims.begin(), dims.end());
  return Handle(H5Screate_simple(int(extent.size()), extent.data(), nullptr), H5Sclose);
}

}  // namespace

void Writer::floats(const std::string& dataset, const std::vector<uint64_t>& dims, const float* values) {
  Handle space = spaceOf(dims);
  Handle d(space.valid() ? H5Dcreate2(m_file.get(), dataset.c_str(), H5T_IEEE_F32LE, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                                      H5P_DEFAULT)
                         : H5I_INVALID_HID,
           H5Dclose);
  if (!d.valid() || H5Dwrite(d.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values) < 0)
    failWrite(dataset, "the HDF5 library refused the dataset " + describeDims(dims));
}

void Writer::doubleScalar(const std::string& dataset, double value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle d(H5Dcreate2(m_file.get(), dataset.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!d.valid() || H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    failWrite(dataset, "the HDF5 library refused the dataset");
}

void Writer::enumeration(const std::string& dataset, const std::vector<std::pair<std::string, int32_t>>& members,
                         int32_t value) {
  Handle type(H5Tenum_create(H5T_NATIVE_INT32), H5Tclose);
  if (!type.valid()) failWrite(dataset, "cannot make its enumeration type");
  for (const auto& [name, v] : members)
    if (H5Tenum_insert(type.get(), name.c_str(), &v) < 0) failWrite(dataset, "cannot make its enumeration type");
  const hsize_t one = 1;
  Handle space(H5Screate_simple(1, &one, nullptr), H5Sclose);
  Handle d(H5Dcreate2(m_file.get(), dataset.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!d.valid() || H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    failWrite(dataset, "the HDF5 library refused the dataset");
}

void Writer::boolean(const std::string& dataset, bool value) {
  Handle type(H5Tenum_create(H5T_NATIVE_INT8), H5Tclose);
  const int8_t no = 0, yes = 1, v = value ? 1 : 0;
  if (!type.valid() || H5Tenum_insert(type.get(), "FALSE", &no) < 0 || H5Tenum_insert(type.get(), "TRUE", &yes) < 0)
    failWrite(dataset, "cannot make its boolean type");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle d(H5Dcreate2(m_file.get(), dataset.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!d.valid() || H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &v) < 0)
    failWrite(dataset, "the HDF5 library refused the dataset");
}

void Writer::string(const std::string& dataset, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), H5T_VARIABLE) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    failWrite(dataset, "cannot make its string type");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle d(H5Dcreate2(m_file.get(), dataset.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  const char* text = value.c_str();
  if (!d.valid() || H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &text) < 0)
    failWrite(dataset, "the HDF5 library refused the dataset");
}

void Writer::empty(const std::string& dataset) {
  Handle space(H5Screate(H5S_NULL), H5Sclose);
  Handle d(H5Dcreate2(m_file.get(), dataset.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!d.valid()) failWrite(dataset, "the HDF5 library refused the dataset");
}

std::string Writer::image() {
  if (H5Fflush(m_file.get(), H5F_SCOPE_GLOBAL) < 0) failWrite("", "cannot flush the file in memory");
  const ssize_t size = H5Fget_file_image(m_file.get(), nullptr, 0);
  if (size <= 0) failWrite("", "cannot take the file's image");
  std::string bytes(size_t(size), '\0');
  if (H5Fget_file_image(m_file.get(), bytes.data(), size_t(size)) != size) failWrite("", "cannot take the file's image");
  return bytes;
}

}  // namespace vktg::io::hdf5
