// The small part of the HDF5 C API the capture files need (src/io/nlos_capture.h), wrapped so that
// every handle is closed on every path and every failure is one vktg::Error "FILE: DATASET:
// problem". HDF5's own error printing is silenced: its messages are replaced by ours. Reads are
// bounded before anything is allocated, and a file may not send the reader elsewhere (external
// links, external or virtual storage).
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace vktg::io::hdf5 {

// The most values one dataset may hold for vktg to read it: 2^28 (1 GiB of float32), a 256 x 256
// confocal scan of 4096 bins.
inline constexpr uint64_t kMaxValues = uint64_t(1) << 28;

// Silences HDF5's error stack printing and its filter-plugin loading (once per process).
void quietLibrary();

// One HDF5 identifier and the function that closes it.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : m_id(id), m_close(close) {}
  Handle(Handle&& other) noexcept : m_id(other.m_id), m_close(other.m_close) { other.m_id = H5I_INVALID_HID; }
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      m_id = other.m_id;
      m_close = other.m_close;
      other.m_id = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t get() const { return m_id; }
  bool valid() const { return m_id >= 0; }

 private:
  void reset() {
    if (m_id >= 0 && m_close) m_close(m_id);
    m_id = H5I_INVALID_HID;
  }
  hid_t m_id = H5I_INVALID_HID;
  herr_t (*m_close)(hid_t) = nullptr;
};

// An open file and the name its errors carry.
struct File {
  Handle handle;
  std::string name;
};

// Opens `path` read-only; not HDF5, unreadable or missing are errors naming it.
File openFile(const std::string& path);
// Opens an HDF5 file image held in memory (`name` names it in errors).
File openImage(const std::string& bytes, const std::string& name);

[[noreturn]] void failAt(const File& file, const std::string& dataset, const std::string& problem);

// A dataset of the root group: its handle, shape (empty for a scalar) and type class.
struct Dataset {
  Handle handle;
  std::string name;
  std::vector<uint64_t> dims;
  bool null = false;      // a dataspace without elements (h5py's Empty, tal's None)
  H5T_class_t typeClass = H5T_NO_CLASS;
  uint64_t count() const;  // elements (1 for a scalar); checked against kMaxValues when opened
};

bool hasLink(const File& file, const std::string& name);
// Opens the dataset `name` of the root group: missing, not a dataset, reached through anything but
// a hard link, stored outside the file, or holding more than kMaxValues values are errors.
Dataset openDataset(const File& file, const std::string& name);
std::optional<Dataset> openOptional(const File& file, const std::string& name);

// "(4, 8, 3)"
std::string describeDims(const std::vector<uint64_t>& dims);

// Streams a numeric (integer or float) dataset's values in C order, converted to double, in
// blocks: `visit(first, values, count)` gets the values at flat indices [first, first + count).
void readBlocks(const File& file, const Dataset& dataset,
                const std::function<void(uint64_t first, const double* values, size_t count)>& visit);
// The whole dataset as floats, each value finite and within float range (else an error naming
// the index).
std::vector<float> readFloats(const File& file, const Dataset& dataset);
// The one value of a dataset holding exactly one number (any shape of one element), finite.
double readScalar(const File& file, const Dataset& dataset);
// The one value of an integer or enumeration dataset of one element (tal's enums, h5py's bools).
int64_t readInteger(const File& file, const Dataset& dataset);
// A string attribute of the root group, if there is one.
std::optional<std::string> readRootStringAttribute(const File& file, const std::string& name);
// A dataset holding one string (scalar), if it is one; nullopt for any other kind.
std::optional<std::string> readString(const File& file, const Dataset& dataset);

// Writing: a file built in memory (the core driver, no backing store) whose bytes then go to disk
// atomically (writeFileAtomic).
class Writer {
 public:
  explicit Writer(std::string name);
  // Datasets of the root group. Values are C order; dims empty for a scalar.
  void floats(const std::string& dataset, const std::vector<uint64_t>& dims, const float* values);
  void doubleScalar(const std::string& dataset, double value);
  // An enumeration of 32-bit integers (one element, shape (1,)), as h5py writes a Python Enum.
  void enumeration(const std::string& dataset, const std::vector<std::pair<std::string, int32_t>>& members, int32_t value);
  // A scalar boolean as h5py writes numpy.bool_: an 8-bit enumeration FALSE = 0, TRUE = 1.
  void boolean(const std::string& dataset, bool value);
  // A scalar variable-length UTF-8 string, as h5py writes a Python str.
  void string(const std::string& dataset, const std::string& value);
  // A dataset with no elements (h5py.Empty(float)): how tal writes None.
  void empty(const std::string& dataset);
  // The file's bytes.
  std::string image();

 private:
  [[noreturn]] void failWrite(const std::string& dataset, const std::string& problem) const;
  std::string m_name;
  Handle m_file;
};

}  // namespace vktg::io::hdf5
