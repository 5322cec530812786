// PNG files decoded back with stb_image, for the CPU-only tests of PNG writers (header-only:
// `unit` tests link no test-support library). It compiles the stb_image implementation (static),
// so include it from one source file per test executable.
#pragma once
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/file_test.h"

namespace vktg::test {

struct DecodedPng {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> pixels;
  const uint8_t* at(int x, int y) const { return &pixels[size_t((y * width + x) * channels)]; }
};

inline DecodedPng decodePng(const std::filesystem::path& path) {
  const std::string bytes = readAll(path);
  EXPECT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  DecodedPng png;
  uint8_t* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &png.width,
                                        &png.height, &png.channels, 0);
  EXPECT_NE(data, nullptr) << stbi_failure_reason();
  if (data) {
    png.pixels.assign(data, data + size_t(png.width) * png.height * png.channels);
    stbi_image_free(data);
  }
  return png;
}

}  // namespace vktg::test
