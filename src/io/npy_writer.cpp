// NumPy .npy (format version 1.0) writer for Python users: dtype little-endian float32, shape
// (H, W, T) in C order, so element [y][x][t] is layer t's pixel (x, y) with row 0 at the top.
#include <bit>
#include <cstring>

#include "io/io_internal.h"

namespace vktg {

static_assert(std::endian::native == std::endian::little, "the .npy writer stores host floats as '<f4'");

void writeNpy(const std::filesystem::path& path, const ImageSet& images) {
  io::validateImageSet(path, images);
  const size_t layerCount = images.layers.size();
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(images.height) + ", " +
                       std::to_string(images.width) + ", " + std::to_string(layerCount) + "), }";
  // Magic (6) + version (2) + header length (2) + header, padded with spaces and ended by '\n' so
  // the data starts on a 64-byte boundary, as the format specification asks.
  constexpr size_t kPrefix = 10;
  const size_t unpadded = kPrefix + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header.push_back('\n');
  const size_t headerLength = header.size();

  std::string bytes("\x93NUMPY\x01\x00", 8);
  bytes.push_back(char(headerLength & 0xff));
  bytes.push_back(char(headerLength >> 8));
  bytes += header;

  const size_t pixelCount = size_t(images.width) * images.height;
  std::vector<float> interleaved(pixelCount * layerCount);
  for (size_t t = 0; t < layerCount; ++t) {
    const std::vector<float>& pixels = images.layers[t].pixels;
    for (size_t i = 0; i < pixelCount; ++i) interleaved[i * layerCount + t] = pixels[i];
  }
  const size_t dataOffset = bytes.size();
  bytes.resize(dataOffset + interleaved.size() * sizeof(float));
  std::memcpy(bytes.data() + dataOffset, interleaved.data(), interleaved.size() * sizeof(float));
  writeFileAtomic(path, bytes);
}

}  // namespace vktg
