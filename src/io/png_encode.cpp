// PNG encoding through stb_image_write. This is the one translation unit in the project that
// compiles the stb_image_write implementation; it is kept static so it can never clash with
// another copy (e.g. a test or a system libstb).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

#include <limits>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg::io {
namespace {

void appendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

}  // namespace

std::string encodePng(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
                      const std::vector<uint8_t>& pixels) {
  const uint64_t rowBytes = uint64_t(width) * uint64_t(channels);
  if (width == 0 || height == 0 || rowBytes > uint64_t(std::numeric_limits<int>::max()) ||
      height > uint32_t(std::numeric_limits<int>::max())) {
    fail(path.string(), "", "cannot encode PNG of size " + std::to_string(width) + "x" + std::to_string(height));
  }
  if (pixels.size() != rowBytes * height) fail(path.string(), "", "internal error: PNG pixel buffer has the wrong size");
  std::string bytes;
  if (!stbi_write_png_to_func(appendBytes, &bytes, int(width), int(height), channels, pixels.data(), int(rowBytes))) {
    fail(path.string(), "", "PNG encoding failed");
  }
  return bytes;
}

}  // namespace vktg::io
