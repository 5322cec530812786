// EXR, NumPy and PNG outputs: exact round trips, graceful errors on bad EXR files, and PNG
// previews decoded back with stb_image to check sizes and colours.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "vktg/error.h"
#include "support/file_test.h"
#include "support/png_decode.h"
#include "vktg/image_io.h"

namespace fs = std::filesystem;

namespace {

using vktg::test::DecodedPng;
using vktg::test::decodePng;
using vktg::test::expectError;
using vktg::test::readAll;
using vktg::test::writePlain;

bool bitwiseEqual(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::vector<std::string> exrChannelNames(const fs::path& path) {
  Imf::InputFile file(path.c_str());
  std::vector<std::string> names;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) names.push_back(it.name());
  return names;
}

int srgbByte(float linear) {
  const float encoded = linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
  return int(std::lround(encoded * 255.0f));
}

class ImageIo : public vktg::test::TempDirTest {};

// Values chosen to expose any lossy path: denormals, negative zero, extremes, non-dyadic fractions.
std::vector<float> awkwardValues(size_t count, float seed) {
  std::vector<float> values(count);
  const float specials[] = {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(), 1.0f / 3.0f, -1e-30f, 65504.5f};
  for (size_t i = 0; i < count; ++i) {
    values[i] = i < std::size(specials) ? specials[i] : seed * std::sin(float(i) * 0.7f + seed) / float(i + 1);
  }
  return values;
}

TEST_F(ImageIo, ExrRoundTripSingleUnnamedLayer) {
  vktg::ImageSet images{7, 5, {{"", awkwardValues(35, 1.5f)}}};
  const fs::path path = m_dir / "single.exr";
  vktg::writeExr(path, images);
  EXPECT_EQ(exrChannelNames(path), std::vector<std::string>{"Y"});
  const vktg::ImageSet read = vktg::readExr(path);
  EXPECT_EQ(read.width, 7u);
  EXPECT_EQ(read.height, 5u);
  ASSERT_EQ(read.layers.size(), 1u);
  EXPECT_EQ(read.layers[0].name, "");
  EXPECT_TRUE(bitwiseEqual(read.layers[0].pixels, images.layers[0].pixels));
  for (float v : read.layers[0].pixels) EXPECT_FALSE(std::isnan(v));
}

TEST_F(ImageIo, ExrRoundTripSingleNamedLayer) {
  vktg::ImageSet images{3, 4, {{"radiance", awkwardValues(12, -2.0f)}}};
  vktg::writeExr(m_dir / "named.exr", images);
  EXPECT_EQ(exrChannelNames(m_dir / "named.exr"), std::vector<std::string>{"radiance.Y"});
  const vktg::ImageSet read = vktg::readExr(m_dir / "named.exr");
  ASSERT_EQ(read.layers.size(), 1u);
  EXPECT_EQ(read.layers[0].name, "radiance");
  EXPECT_TRUE(bitwiseEqual(read.layers[0].pixels, images.layers[0].pixels));
}

// Names that sort differently from their order (bin_10 < bin_2 alphabetically) must come back in
// the order written.
TEST_F(ImageIo, ExrRoundTripMultiLayerPreservesNamesAndOrder) {
  vktg::ImageSet images{9, 6, {}};
  const std::vector<std::string> names = {"bin_2", "bin_10", "d.translate_x", "albedo"};
  for (size_t i = 0; i < names.size(); ++i) images.layers.push_back({names[i], awkwardValues(54, float(i) + 0.25f)});
  const fs::path path = m_dir / "stack.exr";
  vktg::writeExr(path, images);
  EXPECT_EQ(exrChannelNames(path), (std::vector<std::string>{"albedo.Y", "bin_10.Y", "bin_2.Y", "d.translate_x.Y"}));
  const vktg::ImageSet read = vktg::readExr(path);
  EXPECT_EQ(read.width, 9u);
  EXPECT_EQ(read.height, 6u);
  ASSERT_EQ(read.layers.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(read.layers[i].name, names[i]);
    EXPECT_TRUE(bitwiseEqual(read.layers[i].pixels, images.layers[i].pixels)) << names[i];
  }
}

// Row 0 is the top: a file written by OpenEXR directly with a distinct top row reads back with
// that row first; without vktg's order attribute layers come in the file's channel order.
TEST_F(ImageIo, ExrReadsForeignFileTopRowFirst) {
  const int width = 2, height = 3;
  std::vector<float> red = {1, 2, 3, 4, 5, 6}, green = {-1, -2, -3, -4, -5, -6};
  const fs::path path = m_dir / "foreign.exr";
  {
    Imf::Header header(width, height);
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    header.channels().insert("G", Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer frame;
    frame.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(red.data()), 4, 4 * width));
    frame.insert("G", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(green.data()), 4, 4 * width));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  }
  const vktg::ImageSet read = vktg::readExr(path);
  ASSERT_EQ(read.layers.size(), 2u);
  EXPECT_EQ(read.layers[0].name, "G");
  EXPECT_EQ(read.layers[1].name, "R");
  EXPECT_EQ(read.layers[0].pixels, green);
  EXPECT_EQ(read.layers[1].pixels, red);
}

// Found by tools/fuzz experiment: 278 bytes whose header declares attributes far larger than the
// file made OpenEXR allocate over 2 GiB before failing. The header is now checked first.
TEST_F(ImageIo, ExrHeaderDeclaringMoreThanTheFileHoldsIsRejectedCheaply) {
  const std::filesystem::path file = std::filesystem::path(VKTG_TEST_DATA) / "fuzz" / "exr-huge-attribute.exr";
  expectError([&] { vktg::readExr(file); }, {"exr-huge-attribute.exr", "header", "declares"});
  // A well-formed file still passes the check.
  vktg::writeExr(m_dir / "ok.exr", vktg::ImageSet{2, 1, {{"", {1, 2}}}});
  EXPECT_EQ(vktg::readExr(m_dir / "ok.exr").layers.at(0).pixels, (std::vector<float>{1, 2}));
}

TEST_F(ImageIo, ExrWriteRejectsInconsistentSets) {
  expectError([&] { vktg::writeExr(m_dir / "a.exr", vktg::ImageSet{2, 2, {{"x", {1, 2, 3}}}}); }, {"a.exr", "pixels"});
  expectError([&] { vktg::writeExr(m_dir / "b.exr", vktg::ImageSet{2, 1, {{"x", {1, 2}}, {"x", {3, 4}}}}); },
              {"b.exr", "duplicate"});
  expectError([&] { vktg::writeExr(m_dir / "c.exr", vktg::ImageSet{2, 1, {{"", {1, 2}}, {"y", {3, 4}}}}); },
              {"c.exr", "names"});
  expectError([&] { vktg::writeExr(m_dir / "d.exr", vktg::ImageSet{2, 1, {}}); }, {"d.exr", "no layers"});
  expectError([&] { vktg::writeExr(m_dir / "e.exr", vktg::ImageSet{0, 0, {{"", {}}}}); }, {"e.exr", "zero size"});
  EXPECT_TRUE(fs::is_empty(m_dir));
}

TEST_F(ImageIo, ExrWriteIntoMissingDirectoryFails) {
  const fs::path path = m_dir / "nowhere" / "out.exr";
  expectError([&] { vktg::writeExr(path, vktg::ImageSet{1, 1, {{"", {1.0f}}}}); }, {path.string(), "does not exist"});
  EXPECT_TRUE(fs::is_empty(m_dir));
}

TEST_F(ImageIo, ExrReadErrorsNameTheFile) {
  const fs::path missing = m_dir / "missing.exr";
  expectError([&] { vktg::readExr(missing); }, {missing.string(), "does not exist"});

  const fs::path empty = m_dir / "empty.exr";
  writePlain(empty, "");
  expectError([&] { vktg::readExr(empty); }, {empty.string(), "empty"});

  const fs::path garbage = m_dir / "garbage.exr";
  writePlain(garbage, "this is certainly not an OpenEXR file, just some text bytes");
  expectError([&] { vktg::readExr(garbage); }, {garbage.string()});

  // Correct magic number followed by junk: the header parser itself must fail gracefully.
  const fs::path badHeader = m_dir / "bad_header.exr";
  writePlain(badHeader, std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + std::string(200, '\x7f'));
  expectError([&] { vktg::readExr(badHeader); }, {badHeader.string()});

  expectError([&] { vktg::readExr(m_dir); }, {m_dir.string()});
}

// Every truncation of a valid file (cutting the header, the offset table or the pixel data)
// must produce an error naming the file, never a crash or silently zero-filled pixels.
TEST_F(ImageIo, ExrReadRejectsTruncatedFiles) {
  vktg::ImageSet images{16, 16, {{"a", awkwardValues(256, 3.0f)}, {"b", awkwardValues(256, 4.0f)}}};
  const fs::path valid = m_dir / "valid.exr";
  vktg::writeExr(valid, images);
  const std::string bytes = readAll(valid);
  ASSERT_GT(bytes.size(), 100u);
  const fs::path truncated = m_dir / "truncated.exr";
  for (size_t length : {size_t(4), size_t(20), bytes.size() / 4, bytes.size() / 2, bytes.size() - 40, bytes.size() - 1}) {
    writePlain(truncated, bytes.substr(0, length));
    expectError([&] { vktg::readExr(truncated); }, {truncated.string()});
  }
}

TEST_F(ImageIo, ExrReadRejectsNonFloatChannels) {
  const fs::path path = m_dir / "half.exr";
  {
    Imf::Header header(2, 2);
    header.channels().insert("Y", Imf::Channel(Imf::UINT));
    std::vector<uint32_t> values = {1, 2, 3, 4};
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(values.data()), 4, 8));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  expectError([&] { vktg::readExr(path); }, {path.string(), "float"});
}

// OpenEXR refuses to write a file without channels, so one is made by emptying the channel list
// attribute ("channels", type "chlist": entries ended by a null byte) of a valid file.
TEST_F(ImageIo, ExrReadRejectsFileWithoutChannels) {
  const fs::path path = m_dir / "nochannels.exr";
  vktg::writeExr(path, vktg::ImageSet{2, 2, {{"", {1, 2, 3, 4}}}});
  std::string bytes = readAll(path);
  const std::string key("channels\0chlist\0", 16);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const size_t sizeAt = at + key.size();
  uint32_t size = 0;
  std::memcpy(&size, bytes.data() + sizeAt, 4);
  ASSERT_EQ(size, 2u + 16u + 1u);  // "Y\0", pixel type, linear/reserved, sampling, terminator
  const uint32_t emptySize = 1;
  bytes.replace(sizeAt, 4 + size, std::string(reinterpret_cast<const char*>(&emptySize), 4) + std::string(1, '\0'));
  writePlain(path, bytes);
  expectError([&] { vktg::readExr(path); }, {path.string(), "channel"});
}

TEST_F(ImageIo, NpyHeaderAndLayout) {
  const uint32_t width = 3, height = 2;
  vktg::ImageSet images{width, height, {}};
  for (int t = 0; t < 4; ++t) {
    std::vector<float> pixels(width * height);
    for (uint32_t i = 0; i < pixels.size(); ++i) pixels[i] = float(100 * t + i) + 0.5f;
    images.layers.push_back({"t" + std::to_string(t), pixels});
  }
  const fs::path path = m_dir / "stack.npy";
  vktg::writeNpy(path, images);
  const std::string bytes = readAll(path);
  ASSERT_GE(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const size_t headerLength = uint8_t(bytes[8]) | (size_t(uint8_t(bytes[9])) << 8);
  const size_t dataOffset = 10 + headerLength;
  EXPECT_EQ(dataOffset % 64, 0u);
  ASSERT_EQ(bytes.size(), dataOffset + width * height * 4 * sizeof(float));
  const std::string header = bytes.substr(10, headerLength);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_EQ(header.front(), '{');
  EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
  EXPECT_NE(header.find("'shape': (2, 3, 4)"), std::string::npos) << header;
  std::vector<float> data(width * height * 4);
  std::memcpy(data.data(), bytes.data() + dataOffset, data.size() * sizeof(float));
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      for (uint32_t t = 0; t < 4; ++t) {
        EXPECT_EQ(data[(y * width + x) * 4 + t], images.layers[t].pixels[y * width + x]) << y << "," << x << "," << t;
      }
    }
  }
}

TEST_F(ImageIo, PngRadianceExposureAndSrgb) {
  // Values 1..100: the 99th percentile (nearest rank) is 99, which maps to linear 0.9.
  const uint32_t width = 10, height = 10;
  std::vector<float> pixels(width * height);
  for (uint32_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i + 1);
  pixels[0] = 0.0f;
  const fs::path path = m_dir / "radiance.png";
  vktg::writePngRadiance(path, width, height, pixels);
  const DecodedPng png = decodePng(path);
  ASSERT_EQ(png.width, 10);
  ASSERT_EQ(png.height, 10);
  ASSERT_EQ(png.channels, 1);
  const float exposure = 0.9f / 99.0f;
  EXPECT_EQ(*png.at(0, 0), 0);
  EXPECT_EQ(*png.at(8, 9), srgbByte(0.9f));  // value 99
  EXPECT_EQ(*png.at(9, 9), srgbByte(100.0f * exposure));
  EXPECT_EQ(*png.at(9, 0), srgbByte(10.0f * exposure));  // row 0 at the top
  EXPECT_EQ(*png.at(0, 1), srgbByte(11.0f * exposure));
}

TEST_F(ImageIo, PngRadianceAllZeroIsBlackAndNaNIsZero) {
  vktg::writePngRadiance(m_dir / "zero.png", 4, 3, std::vector<float>(12, 0.0f));
  const DecodedPng zero = decodePng(m_dir / "zero.png");
  ASSERT_EQ(zero.width, 4);
  ASSERT_EQ(zero.height, 3);
  for (uint8_t v : zero.pixels) EXPECT_EQ(v, 0);

  std::vector<float> pixels = {1.0f, std::nanf(""), std::numeric_limits<float>::infinity(), 1.0f};
  vktg::writePngRadiance(m_dir / "nan.png", 2, 2, pixels);
  const DecodedPng png = decodePng(m_dir / "nan.png");
  EXPECT_EQ(*png.at(0, 0), srgbByte(0.9f));  // infinity does not take part in the exposure
  EXPECT_EQ(*png.at(1, 0), 0);
  EXPECT_EQ(*png.at(0, 1), 0);
}

TEST_F(ImageIo, PngRadianceRejectsWrongPixelCount) {
  expectError([&] { vktg::writePngRadiance(m_dir / "bad.png", 4, 4, std::vector<float>(15)); }, {"bad.png"});
  EXPECT_TRUE(fs::is_empty(m_dir));
}

TEST_F(ImageIo, PngDivergingColours) {
  const std::vector<float> pixels = {-2.0f, -1.0f, 0.0f, 1.0f, 2.0f, std::nanf("")};
  const float scale = vktg::writePngDiverging(m_dir / "div.png", 3, 2, pixels);
  EXPECT_EQ(scale, 2.0f);
  const DecodedPng png = decodePng(m_dir / "div.png");
  ASSERT_EQ(png.width, 3);
  ASSERT_EQ(png.height, 2);
  ASSERT_EQ(png.channels, 3);
  auto rgb = [&](int x, int y) {
    const uint8_t* p = png.at(x, y);
    return std::vector<int>{p[0], p[1], p[2]};
  };
  EXPECT_EQ(rgb(0, 0), (std::vector<int>{0, 0, 255}));      // -scale: blue
  EXPECT_EQ(rgb(1, 0), (std::vector<int>{128, 128, 255}));  // -scale/2
  EXPECT_EQ(rgb(2, 0), (std::vector<int>{255, 255, 255}));  // zero: white
  EXPECT_EQ(rgb(0, 1), (std::vector<int>{255, 128, 128}));  // +scale/2
  EXPECT_EQ(rgb(1, 1), (std::vector<int>{255, 0, 0}));      // +scale: red
  EXPECT_EQ(rgb(2, 1), (std::vector<int>{255, 255, 255}));  // NaN drawn as zero
}

TEST_F(ImageIo, PngDivergingScaleIgnoresFireflyAndZeroImageIsWhite) {
  std::vector<float> pixels(1000, -1.0f);
  pixels[17] = 1e6f;
  EXPECT_EQ(vktg::writePngDiverging(m_dir / "firefly.png", 100, 10, pixels), 1.0f);
  const DecodedPng firefly = decodePng(m_dir / "firefly.png");
  EXPECT_EQ(std::vector<int>(firefly.at(0, 0), firefly.at(0, 0) + 3), (std::vector<int>{0, 0, 255}));
  EXPECT_EQ(std::vector<int>(firefly.at(17, 0), firefly.at(17, 0) + 3), (std::vector<int>{255, 0, 0}));

  EXPECT_EQ(vktg::writePngDiverging(m_dir / "zero.png", 5, 4, std::vector<float>(20, 0.0f)), 0.0f);
  const DecodedPng zero = decodePng(m_dir / "zero.png");
  ASSERT_EQ(zero.width, 5);
  ASSERT_EQ(zero.height, 4);
  for (uint8_t v : zero.pixels) EXPECT_EQ(v, 255);
}

TEST_F(ImageIo, PngContactSheetSharesOneExposure) {
  // Three constant 4x2 layers 0, 1, 2: the shared 99th percentile is 2, so layer 1 shows at
  // linear 0.45 (a per-layer exposure would show it at 0.9). Tiles this small are magnified 16x
  // (to 64 pixels across).
  vktg::ImageSet images{4, 2, {}};
  for (int t = 0; t < 3; ++t) images.layers.push_back({"bin" + std::to_string(t), std::vector<float>(8, float(t))});
  vktg::writePngContactSheet(m_dir / "sheet.png", images);
  const DecodedPng png = decodePng(m_dir / "sheet.png");
  const int gap = 2;
  ASSERT_EQ(png.width, 3 * 64 + 4 * gap);
  ASSERT_EQ(png.height, 32 + 2 * gap);
  ASSERT_EQ(png.channels, 1);
  EXPECT_EQ(*png.at(0, 0), *png.at(png.width - 1, png.height - 1));  // background border
  for (int t = 0; t < 3; ++t) {
    const int left = gap + t * (64 + gap);
    const int expected = srgbByte(0.45f * float(t));
    EXPECT_EQ(*png.at(left, gap), expected) << t;
    EXPECT_EQ(*png.at(left + 63, gap + 31), expected) << t;
  }
}

TEST_F(ImageIo, PngContactSheetMagnifiesEachPixelIntoABlock) {
  // A 2x1 layer, left pixel 1 and right 0: magnified 32x, the left 32 columns bright, the rest black.
  vktg::ImageSet images{2, 1, {{"bin0", {1.0f, 0.0f}}, {"bin1", {1.0f, 0.0f}}}};
  vktg::writePngContactSheet(m_dir / "magnified.png", images);
  const DecodedPng png = decodePng(m_dir / "magnified.png");
  const int gap = 2;
  ASSERT_EQ(png.width, 2 * 64 + 3 * gap);
  ASSERT_EQ(png.height, 32 + 2 * gap);
  EXPECT_EQ(*png.at(gap + 31, gap + 31), srgbByte(0.9f));
  EXPECT_EQ(*png.at(gap + 32, gap), srgbByte(0.0f));
  EXPECT_EQ(*png.at(gap + 63, gap + 31), srgbByte(0.0f));
}

TEST_F(ImageIo, PngContactSheetWrapsAtSixteenColumnsAndShrinksLargeLayers) {
  vktg::ImageSet images{300, 10, {}};
  for (int t = 0; t < 20; ++t) images.layers.push_back({"t" + std::to_string(t), std::vector<float>(3000, 1.0f)});
  vktg::writePngContactSheet(m_dir / "wide.png", images);
  const DecodedPng png = decodePng(m_dir / "wide.png");
  // 300 px shrinks by 3 to 100x4 tiles; 20 layers make 16 columns and 2 rows.
  EXPECT_EQ(png.width, 16 * 100 + 17 * 2);
  EXPECT_EQ(png.height, 2 * 4 + 3 * 2);
  EXPECT_EQ(*png.at(2, 2), srgbByte(0.9f));
}

}  // namespace
