// Helpers shared by the image writers in src/io; not part of the public interface.
#pragma once
#include <array>
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

// Tone mapping and colours shared by the PNG previews and the optimisation plots (src/opt/plot.cpp).
// Exposure multiplier for radiance previews of these layers together (the 99th percentile of the
// finite positive values maps near white); 0 when there is nothing positive to show.
float radianceExposure(const std::vector<const std::vector<float>*>& layers);
// An sRGB grey level for one radiance value (non-finite values are drawn as 0).
uint8_t radianceGrey(float value, float exposure);
// Diverging colour for t in [-1, 1]: blue at -1, white at 0, red at +1 (t is clamped).
std::array<uint8_t, 3> divergingColor(float t);
// Box-filters a layer down by an integer factor to tileWidth x tileHeight; partial blocks at the
// edges average what they cover, non-finite pixels count as 0.
std::vector<float> downsample(const std::vector<float>& pixels, uint32_t width, uint32_t height, uint32_t factor,
                              uint32_t tileWidth, uint32_t tileHeight);
// The same with a factor per axis (columns by factorX, rows by factorY).
std::vector<float> downsample(const std::vector<float>& pixels, uint32_t width, uint32_t height, uint32_t factorX,
                              uint32_t factorY, uint32_t tileWidth, uint32_t tileHeight);

// A short lower-case description of an errno value for user-facing messages.
std::string describeErrno(int error);

}  // namespace vktg::io
