// Shape checks shared by every writer, so a malformed ImageSet is reported before any file is touched.
#include <cctype>
#include <cerrno>
#include <cstring>
#include <set>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg::io {

void validateImage(const std::filesystem::path& path, uint32_t width, uint32_t height, size_t pixelCount) {
  if (width == 0 || height == 0) {
    fail(path.string(), "", "image has zero size (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  const uint64_t expected = uint64_t(width) * height;
  if (pixelCount != expected) {
    fail(path.string(), "", "image has " + std::to_string(pixelCount) + " pixels, expected " + std::to_string(width) +
                                "x" + std::to_string(height) + " = " + std::to_string(expected));
  }
}

void validateImageSet(const std::filesystem::path& path, const ImageSet& images) {
  if (images.layers.empty()) fail(path.string(), "", "image set has no layers");
  std::set<std::string> names;
  for (const ImageLayer& layer : images.layers) {
    validateImage(path, images.width, images.height, layer.pixels.size());
    if (!names.insert(layer.name).second) fail(path.string(), "layer '" + layer.name + "'", "duplicate layer name");
  }
  // An unnamed layer is only unambiguous when it is the only one (it becomes channel "Y").
  if (images.layers.size() > 1 && names.count("")) fail(path.string(), "", "layers of a multi-layer set need names");
}

std::string describeErrno(int error) {
  switch (error) {
    case ENOENT: return "directory does not exist";
    case ENOTDIR: return "a component of the path is not a directory";
    case EACCES:
    case EPERM: return "permission denied";
    case EROFS: return "read-only file system";
    case ENOSPC: return "no space left on device";
    case EDQUOT: return "disk quota exceeded";
    case EISDIR: return "is a directory";
    case ENAMETOOLONG: return "file name too long";
    default: {
      std::string text = std::strerror(error);
      if (!text.empty()) text[0] = char(std::tolower(static_cast<unsigned char>(text[0])));
      return text;
    }
  }
}

}  // namespace vktg::io
