// OpenEXR reading and writing. Files are encoded to and decoded from memory so that writing can
// go through writeFileAtomic and reading never leaves OpenEXR holding a half-read file; every
// OpenEXR exception becomes a vktg::Error naming the file.
//
// Layout: one FLOAT channel per layer, named "<layer>.Y" ("Y" for a lone unnamed layer), ZIP
// compression (lossless). EXR stores channels sorted by name, so the writer also records the
// layer order in the string-vector attribute kLayerOrderAttribute; readExr returns layers in that
// order when it matches the channels, otherwise in the file's (alphabetical) channel order.
#include <OpenEXR/Iex.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringVectorAttribute.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <utility>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr const char* kLayerOrderAttribute = "vktgLayerOrder";
constexpr const char* kChannelSuffix = ".Y";
constexpr char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
// Refuse headers describing absurd images before allocating (a corrupt or hostile header must
// produce an error, not an out-of-memory abort).
constexpr int64_t kMaxDimension = 1 << 16;
constexpr int64_t kMaxSamples = int64_t(1) << 30;

class MemoryOStream : public Imf::OStream {
 public:
  explicit MemoryOStream(const std::string& name) : Imf::OStream(name.c_str()) {}
  void write(const char c[], int n) override {
    if (m_position + size_t(n) > m_bytes.size()) m_bytes.resize(m_position + size_t(n));
    std::memcpy(m_bytes.data() + m_position, c, size_t(n));
    m_position += size_t(n);
  }
  uint64_t tellp() override { return m_position; }
  void seekp(uint64_t position) override { m_position = position; }
  const std::string& bytes() const { return m_bytes; }

 private:
  std::string m_bytes;
  size_t m_position = 0;
};

class MemoryIStream : public Imf::IStream {
 public:
  MemoryIStream(const std::string& name, const std::string& bytes) : Imf::IStream(name.c_str()), m_bytes(bytes) {}
  bool read(char c[], int n) override {
    if (m_position > m_bytes.size() || size_t(n) > m_bytes.size() - m_position) {
      throw Iex::InputExc("unexpected end of file");
    }
    std::memcpy(c, m_bytes.data() + m_position, size_t(n));
    m_position += size_t(n);
    return m_position < m_bytes.size();
  }
  uint64_t tellg() override { return m_position; }
  void seekg(uint64_t position) override { m_position = position; }

 private:
  const std::string& m_bytes;
  uint64_t m_position = 0;
};

std::string channelName(const ImageSet& images, const ImageLayer& layer) {
  if (images.layers.size() == 1 && layer.name.empty()) return "Y";
  return layer.name + kChannelSuffix;
}

std::string layerName(const std::string& channel) {
  if (channel == "Y") return "";
  const size_t suffix = std::strlen(kChannelSuffix);
  if (channel.size() > suffix && channel.compare(channel.size() - suffix, suffix, kChannelSuffix) == 0) {
    return channel.substr(0, channel.size() - suffix);
  }
  return channel;  // a channel from another tool ("R", "depth") keeps its full name
}

const char* pixelTypeName(Imf::PixelType type) {
  switch (type) {
    case Imf::HALF: return "16-bit half float";
    case Imf::UINT: return "32-bit unsigned integer";
    default: return "unknown";
  }
}

std::string readFileBytes(const fs::path& path) {
  std::error_code error;
  if (!fs::exists(path, error)) fail(path.string(), "", "cannot read: file does not exist");
  if (fs::is_directory(path, error)) fail(path.string(), "", "cannot read: it is a directory");
  std::ifstream stream(path, std::ios::binary);
  if (!stream) fail(path.string(), "", "cannot read: " + io::describeErrno(errno));
  std::string bytes((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
  if (stream.bad()) fail(path.string(), "", "cannot read: I/O error");
  return bytes;
}

// Layer order recorded by writeExr, if it names exactly the layers present; otherwise file order.
void applyRecordedOrder(const Imf::Header& header, ImageSet& images) {
  const auto* order = header.findTypedAttribute<Imf::StringVectorAttribute>(kLayerOrderAttribute);
  if (!order || order->value().size() != images.layers.size()) return;
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < images.layers.size(); ++i) index[images.layers[i].name] = i;
  std::vector<ImageLayer> ordered;
  for (const std::string& name : order->value()) {
    auto found = index.find(name);
    if (found == index.end() || found->second == SIZE_MAX) return;  // unknown or repeated name
    ordered.push_back(std::move(images.layers[found->second]));
    found->second = SIZE_MAX;
  }
  images.layers = std::move(ordered);
}

// The data window's width and height, refused when empty or beyond kMaxDimension.
std::pair<int64_t, int64_t> checkedSize(const std::string& name, const Imath::Box2i& window) {
  const int64_t width = int64_t(window.max.x) - window.min.x + 1;
  const int64_t height = int64_t(window.max.y) - window.min.y + 1;
  if (width <= 0 || height <= 0) fail(name, "dataWindow", "empty data window");
  if (width > kMaxDimension || height > kMaxDimension) {
    fail(name, "dataWindow", "image too large (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  return {width, height};
}

ImageSet decodeExr(const fs::path& path, const std::string& bytes) {
  const std::string name = path.string();
  MemoryIStream stream(name, bytes);
  Imf::InputFile file(stream, 1);
  const Imf::Header& header = file.header();
  const Imath::Box2i window = header.dataWindow();
  const auto [width, height] = checkedSize(name, window);

  ImageSet images;
  images.width = uint32_t(width);
  images.height = uint32_t(height);
  const Imf::ChannelList& channels = header.channels();
  for (auto it = channels.begin(); it != channels.end(); ++it) {
    const std::string channel = it.name();
    if (it.channel().type != Imf::FLOAT) {
      fail(name, "channel '" + channel + "'", std::string("pixel type is ") + pixelTypeName(it.channel().type) +
                                                  "; only 32-bit float channels are supported");
    }
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1) {
      fail(name, "channel '" + channel + "'", "subsampled channels are not supported");
    }
    images.layers.push_back({layerName(channel), {}});
  }
  if (images.layers.empty()) fail(name, "", "the file has no channels");
  if (int64_t(images.layers.size()) * width * height > kMaxSamples) fail(name, "", "image too large");
  if (!file.isComplete()) fail(name, "", "the file is truncated (pixel data missing)");

  Imf::FrameBuffer frameBuffer;
  size_t layerIndex = 0;
  for (auto it = channels.begin(); it != channels.end(); ++it, ++layerIndex) {
    std::vector<float>& pixels = images.layers[layerIndex].pixels;
    pixels.assign(size_t(width * height), 0.0f);
    frameBuffer.insert(it.name(), Imf::Slice::Make(Imf::FLOAT, pixels.data(), window, sizeof(float),
                                                   sizeof(float) * size_t(width)));
  }
  file.setFrameBuffer(frameBuffer);
  file.readPixels(window.min.y, window.max.y);
  applyRecordedOrder(header, images);
  return images;
}

}  // namespace

void writeExr(const fs::path& path, const ImageSet& images) {
  io::validateImageSet(path, images);
  std::string bytes;
  try {
    Imf::Header header(int(images.width), int(images.height));
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frameBuffer;
    std::vector<std::string> order;
    for (const ImageLayer& layer : images.layers) {
      const std::string channel = channelName(images, layer);
      header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
      // OpenEXR's Slice takes a mutable pointer but only reads through it when writing.
      char* base = reinterpret_cast<char*>(const_cast<float*>(layer.pixels.data()));
      frameBuffer.insert(channel, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * images.width));
      order.push_back(layer.name);
    }
    header.insert(kLayerOrderAttribute, Imf::StringVectorAttribute(order));
    MemoryOStream stream(path.string());
    {
      // The line offset table is written when the OutputFile is destroyed, so it must go first.
      Imf::OutputFile file(stream, header, 1);
      file.setFrameBuffer(frameBuffer);
      file.writePixels(int(images.height));
    }
    bytes = stream.bytes();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path.string(), "", std::string("cannot encode OpenEXR: ") + e.what());
  }
  writeFileAtomic(path, bytes);
}

static uint32_t littleEndian32(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (int k = 3; k >= 0; --k) value = (value << 8) | uint8_t(bytes[at + size_t(k)]);
  return value;
}

// Bytes a value of each fixed-size attribute type holds. OpenEXR reads that many whatever size the
// attribute declares, and then reads the next attribute from where it stopped, so a declared size
// that differs would let the rest of the header be parsed from inside this attribute, out of
// step with the checks here.
static int fixedAttributeSize(const std::string& type) {
  static const std::map<std::string, int> sizes = {
      {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8}, {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28}, {"lineOrder", 1},
      {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"rational", 8}, {"tiledesc", 9},
      {"timecode", 8}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}};
  const auto found = sizes.find(type);
  return found == sizes.end() ? -1 : found->second;
}

// Checks an attribute's value against what OpenEXR will read of it: fixed-size types hold exactly
// their size, a channel list ends (with its empty name) exactly at the declared size, and the
// lengths OpenEXR allocates for before reading stay inside the attribute: each string of a
// "stringvector" and a "preview" image (width x height RGBA8 pixels). A hostile header declaring
// gigabytes there within a few bytes would otherwise be allocated for.
static void checkAttributeContents(const fs::path& path, const std::string& bytes, const std::string& name,
                                   const std::string& type, size_t at, uint32_t size) {
  const size_t end = at + size;
  const std::string held = std::to_string(size) + " bytes";
  auto bad = [&](const std::string& problem) {
    fail(path.string(), "header", "attribute \"" + name + "\" (" + type + "): " + problem);
  };
  if (const int fixed = fixedAttributeSize(type); fixed >= 0) {
    if (size != uint32_t(fixed)) bad("declares " + held + ", but a " + type + " holds " + std::to_string(fixed));
    // Opening the file sizes its decompression buffers by the data window: a few hundred bytes
    // declaring a 10^7-pixel-wide image would allocate gigabytes.
    if (name == "dataWindow" && type == "box2i") {
      auto corner = [&](size_t k) { return int(int32_t(littleEndian32(bytes, at + 4 * k))); };
      checkedSize(path.string(), Imath::Box2i(Imath::V2i(corner(0), corner(1)), Imath::V2i(corner(2), corner(3))));
    }
  } else if (type == "chlist") {
    size_t p = at;
    for (;;) {  // entries: a name, pixel type, pLinear, 3 reserved bytes, x and y sampling
      const size_t nameEnd = bytes.find('\0', p);
      if (nameEnd == std::string::npos || nameEnd >= end) bad("its channel list does not end within its " + held);
      if (nameEnd == p) {
        p = nameEnd + 1;
        break;
      }
      p = nameEnd + 1 + 16;
      if (p > end) bad("its channel list does not end within its " + held);
    }
    if (p != end) bad("its channel list ends after " + std::to_string(p - at) + " of its " + held);
  } else if (type == "stringvector") {
    for (size_t k = 0, p = at; p < end; ++k) {
      if (end - p < 4) bad("string " + std::to_string(k) + " has a truncated length");
      const int32_t length = int32_t(littleEndian32(bytes, p));
      p += 4;
      if (length < 0 || uint64_t(length) > end - p)
        bad("string " + std::to_string(k) + " declares " + std::to_string(length) + " bytes, more than its " + held +
            " hold");
      p += size_t(length);
    }
  } else if (type == "preview") {
    if (size < 8) bad("a preview needs at least 8 bytes, not " + held);
    // width x height fits 64 bits; four bytes a pixel might not, so compare pixels.
    const uint64_t width = littleEndian32(bytes, at), height = littleEndian32(bytes, at + 4);
    if (width * height > (size - 8) / 4)
      bad("its " + std::to_string(width) + " x " + std::to_string(height) + " preview needs " +
          std::to_string(width * height) + " pixels of 4 bytes, more than its " + held + " hold");
  }
}

// OpenEXR trusts the sizes a header declares: a few hundred bytes claiming a gigabyte-sized
// attribute make it allocate that much before it notices the file is short (found by fuzzing).
// Every attribute (name, type, int32 size, value) must fit in the file; checked before decoding.
static void checkHeaderSizes(const fs::path& path, const std::string& bytes) {
  const bool multipart = (uint8_t(bytes[5]) & 0x10) != 0;  // version field bit 12
  size_t at = 8;
  auto cString = [&](const char* what) {
    const size_t end = bytes.find('\0', at);
    if (end == std::string::npos) fail(path.string(), "header", std::string("truncated in an attribute's ") + what);
    std::string text = bytes.substr(at, end - at);
    at = end + 1;
    return text;
  };
  for (;;) {  // headers (one, or a list ended by an empty one for multi-part files)
    if (at >= bytes.size()) fail(path.string(), "header", "truncated");
    if (bytes[at] == '\0') {
      ++at;
      if (!multipart || (at < bytes.size() && bytes[at] == '\0')) return;
      continue;
    }
    const std::string name = cString("name");
    const std::string type = cString("type");
    if (bytes.size() - at < 4) fail(path.string(), "header", "truncated in attribute \"" + name + "\"");
    const uint32_t size = littleEndian32(bytes, at);
    at += 4;
    if (size > bytes.size() - at)
      fail(path.string(), "header", "attribute \"" + name + "\" declares " + std::to_string(size) + " bytes but only " +
                                        std::to_string(bytes.size() - at) + " remain in the file");
    checkAttributeContents(path, bytes, name, type, at, size);
    at += size;
  }
}

ImageSet readExr(const fs::path& path) {
  const std::string bytes = readFileBytes(path);
  if (bytes.empty()) fail(path.string(), "", "not an OpenEXR file (the file is empty)");
  if (bytes.size() < sizeof(kExrMagic) || std::memcmp(bytes.data(), kExrMagic, sizeof(kExrMagic)) != 0) {
    fail(path.string(), "", "not an OpenEXR file (wrong magic number)");
  }
  if (bytes.size() < 8) fail(path.string(), "header", "truncated");
  checkHeaderSizes(path, bytes);
  try {
    return decodeExr(path, bytes);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path.string(), "", "malformed OpenEXR file (out of memory while decoding)");
  } catch (const std::exception& e) {
    fail(path.string(), "", std::string("malformed OpenEXR file: ") + e.what());
  }
}

}  // namespace vktg
