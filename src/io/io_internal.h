// Helpers shared by the image writers in src/io; not part of the public interface.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vktg/image_io.h"

namespace vktg::io {

// Throws vktg::Error naming `path` unless the set is non-empty, every layer has width*height
// pixels and the layer names are distinct.
void validateImageSet(const std::filesystem::path& path, const ImageSet& images);

// Throws vktg::Error naming `path` unless width, height > 0 and pixels.size() == width*height.
void validateImage(const std::filesystem::path& path, uint32_t width, uint32_t height, size_t pixelCount);

// Encodes 8-bit pixels (1 = grey, 3 = RGB channels, rows top to bottom) as PNG bytes in memory.
std::string encodePng(const std::filesystem::path& path, uint32_t width, uint32_t height, int channels,
                      const std::vector<uint8_t>& pixels);

// A short lower-case description of an errno value for user-facing messages.
std::string describeErrno(int error);

}  // namespace vktg::io
