// 8-bit PNG previews of float images: tone-mapped radiance (grey), a diverging colour map for
// signed derivative images, and a contact sheet of a transient stack.
//
// Non-finite pixels should never reach a preview; if they do they are drawn as 0 (black in a
// radiance preview, white in the diverging map), excluded from the exposure/scale statistics,
// and counted in a warning on stderr so they are not silently hidden.
#include <algorithm>
#include <cmath>
#include <iostream>

#include "io/io_internal.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// The 99th percentile of the finite positive values maps to this linear value, so highlights
// keep some headroom and a few fireflies saturate instead of darkening the whole image.
constexpr float kRadianceTarget = 0.9f;
constexpr double kRadiancePercentile = 0.99;
// Diverging scale: 99.5th percentile of |v| over finite non-zero pixels (robust to isolated
// fireflies, unlike the maximum; zeros are excluded because derivative images are often sparse).
constexpr double kDivergingPercentile = 0.995;
constexpr uint32_t kContactColumns = 16;
constexpr uint32_t kContactTileSize = 128;  // longest tile side; larger layers are box-filtered down
// Smaller layers (a scan's grid of a few points) are magnified by a whole factor to at least this.
constexpr uint32_t kContactMinTile = 64;
constexpr uint32_t kContactGap = 2;
constexpr uint8_t kContactBackground = 96;

// Value at rank floor(q * (n - 1)) of a non-empty sample (nearest-rank, no interpolation).
float percentile(std::vector<float> values, double q) {
  const size_t rank = size_t(q * double(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank), values.end());
  return values[rank];
}

void warnNonFinite(const fs::path& path, size_t count) {
  if (count == 0) return;
  std::cerr << "vktg: warning: " << path.string() << ": " << count << " non-finite pixel(s) drawn as 0\n";
}

size_t countNonFinite(const std::vector<float>& pixels) {
  return size_t(std::count_if(pixels.begin(), pixels.end(), [](float v) { return !std::isfinite(v); }));
}

float srgbEncode(float linear) {
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

uint8_t toByte(float unit) { return uint8_t(std::lround(std::clamp(unit, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

namespace io {

float radianceExposure(const std::vector<const std::vector<float>*>& layers) {
  std::vector<float> positive;
  for (const std::vector<float>* pixels : layers) {
    for (float v : *pixels) {
      if (std::isfinite(v) && v > 0.0f) positive.push_back(v);
    }
  }
  if (positive.empty()) return 0.0f;
  return kRadianceTarget / percentile(std::move(positive), kRadiancePercentile);
}

uint8_t radianceGrey(float value, float exposure) {
  if (!std::isfinite(value)) value = 0.0f;
  return toByte(srgbEncode(std::clamp(value * exposure, 0.0f, 1.0f)));
}

std::vector<float> downsample(const std::vector<float>& pixels, uint32_t width, uint32_t height, uint32_t factor,
                              uint32_t tileWidth, uint32_t tileHeight) {
  return downsample(pixels, width, height, factor, factor, tileWidth, tileHeight);
}

std::vector<float> downsample(const std::vector<float>& pixels, uint32_t width, uint32_t height, uint32_t factorX,
                              uint32_t factorY, uint32_t tileWidth, uint32_t tileHeight) {
  std::vector<float> tile(size_t(tileWidth) * tileHeight);
  for (uint32_t ty = 0; ty < tileHeight; ++ty) {
    for (uint32_t tx = 0; tx < tileWidth; ++tx) {
      double sum = 0.0;
      uint32_t count = 0;
      for (uint32_t y = ty * factorY; y < std::min(height, (ty + 1) * factorY); ++y) {
        for (uint32_t x = tx * factorX; x < std::min(width, (tx + 1) * factorX); ++x) {
          const float v = pixels[size_t(y) * width + x];
          sum += std::isfinite(v) ? v : 0.0f;
          ++count;
        }
      }
      tile[size_t(ty) * tileWidth + tx] = float(sum / count);
    }
  }
  return tile;
}

std::array<uint8_t, 3> divergingColor(float t) {
  t = std::clamp(t, -1.0f, 1.0f);
  // White at zero, fading linearly to pure red (positive) or pure blue (negative) at |t| = 1.
  const uint8_t fade = toByte(1.0f - std::abs(t));
  return {t < 0.0f ? fade : uint8_t(255), fade, t > 0.0f ? fade : uint8_t(255)};
}

}  // namespace io

void writePngRadiance(const fs::path& path, uint32_t width, uint32_t height, const std::vector<float>& pixels) {
  io::validateImage(path, width, height, pixels.size());
  const float exposure = io::radianceExposure({&pixels});
  std::vector<uint8_t> grey(pixels.size());
  std::transform(pixels.begin(), pixels.end(), grey.begin(), [&](float v) { return io::radianceGrey(v, exposure); });
  const std::string png = io::encodePng(path, width, height, 1, grey);
  writeFileAtomic(path, png);
  warnNonFinite(path, countNonFinite(pixels));
}

float writePngDiverging(const fs::path& path, uint32_t width, uint32_t height, const std::vector<float>& pixels) {
  io::validateImage(path, width, height, pixels.size());
  std::vector<float> magnitudes;
  for (float v : pixels) {
    if (std::isfinite(v) && v != 0.0f) magnitudes.push_back(std::abs(v));
  }
  const float scale = magnitudes.empty() ? 0.0f : percentile(std::move(magnitudes), kDivergingPercentile);
  std::vector<uint8_t> rgb(pixels.size() * 3);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const float v = std::isfinite(pixels[i]) && scale > 0.0f ? pixels[i] / scale : 0.0f;
    const std::array<uint8_t, 3> colour = io::divergingColor(v);
    std::copy(colour.begin(), colour.end(), rgb.begin() + std::ptrdiff_t(3 * i));
  }
  const std::string png = io::encodePng(path, width, height, 3, rgb);
  writeFileAtomic(path, png);
  warnNonFinite(path, countNonFinite(pixels));
  return scale;
}

void writePngContactSheet(const fs::path& path, const ImageSet& images) {
  io::validateImageSet(path, images);
  const uint32_t factor = std::max(1u, (std::max(images.width, images.height) + kContactTileSize - 1) / kContactTileSize);
  const uint32_t shrunkWidth = (images.width + factor - 1) / factor;
  const uint32_t shrunkHeight = (images.height + factor - 1) / factor;
  const uint32_t magnify = std::max(1u, kContactMinTile / std::max(shrunkWidth, shrunkHeight));
  const uint32_t tileWidth = shrunkWidth * magnify, tileHeight = shrunkHeight * magnify;
  const uint32_t count = uint32_t(images.layers.size());
  const uint32_t columns = std::min(count, kContactColumns);
  const uint32_t rows = (count + columns - 1) / columns;
  const uint32_t sheetWidth = columns * tileWidth + (columns + 1) * kContactGap;
  const uint32_t sheetHeight = rows * tileHeight + (rows + 1) * kContactGap;

  std::vector<std::vector<float>> tiles;
  std::vector<const std::vector<float>*> tilePointers;
  size_t nonFinite = 0;
  for (const ImageLayer& layer : images.layers) {
    tiles.push_back(io::downsample(layer.pixels, images.width, images.height, factor, shrunkWidth, shrunkHeight));
    nonFinite += countNonFinite(layer.pixels);
  }
  for (const std::vector<float>& tile : tiles) tilePointers.push_back(&tile);
  // One exposure for the whole stack so brightness is comparable from bin to bin.
  const float exposure = io::radianceExposure(tilePointers);

  std::vector<uint8_t> sheet(size_t(sheetWidth) * sheetHeight, kContactBackground);
  for (uint32_t index = 0; index < count; ++index) {
    const uint32_t left = kContactGap + (index % columns) * (tileWidth + kContactGap);
    const uint32_t top = kContactGap + (index / columns) * (tileHeight + kContactGap);
    for (uint32_t y = 0; y < tileHeight; ++y) {
      for (uint32_t x = 0; x < tileWidth; ++x) {
        sheet[size_t(top + y) * sheetWidth + left + x] =
            io::radianceGrey(tiles[index][size_t(y / magnify) * shrunkWidth + x / magnify], exposure);
      }
    }
  }
  const std::string png = io::encodePng(path, sheetWidth, sheetHeight, 1, sheet);
  writeFileAtomic(path, png);
  warnNonFinite(path, nonFinite);
}

}  // namespace vktg
