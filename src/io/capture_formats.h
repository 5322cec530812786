// The two capture layouts readCapture tells apart (src/io/nlos_capture.h): each reads an open file
// into a Capture, checking shapes against each other before reading H's values.
#pragma once
#include "io/hdf5_file.h"
#include "io/nlos_capture.h"

namespace vktg::io {

Capture readTalCapture(const hdf5::File& file);
Capture readZaragozaCapture(const hdf5::File& file);

// tal's enums as tal/enums.py numbers them, every member (h5py writes them all into the type).
const std::vector<std::pair<std::string, int32_t>>& talHFormatMembers();
const std::vector<std::pair<std::string, int32_t>>& talGridFormatMembers();
inline constexpr int32_t kGridFormatN3 = 1, kGridFormatXY3 = 2;

}  // namespace vktg::io
