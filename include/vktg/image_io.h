// Image outputs: OpenEXR (single channel float32 per layer, multi-layer for stacks and derivative
// sets), PNG previews, NumPy arrays. Every write goes to a temporary file in the target directory
// and is renamed into place, so a failed run never leaves a partial or overwritten result.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vktg {

// One named single-channel float image, row-major, row 0 at the top.
struct ImageLayer {
  std::string name;
  std::vector<float> pixels;
};

struct ImageSet {
  uint32_t width = 0, height = 0;
  std::vector<ImageLayer> layers;

  // Every layer's pixels, layer after layer (the layout of a film and of an adjoint image).
  std::vector<float> allPixels() const {
    std::vector<float> out;
    for (const ImageLayer& layer : layers) out.insert(out.end(), layer.pixels.begin(), layer.pixels.end());
    return out;
  }
};

// Multi-layer EXR: channel names "<layer>.Y" (or "Y" for a single unnamed layer). Throws vktg::Error.
void writeExr(const std::filesystem::path& path, const ImageSet& images);
ImageSet readExr(const std::filesystem::path& path);  // throws vktg::Error naming the file

// Tone-mapped radiance preview of one layer (exposure so the 99th percentile maps near white, sRGB).
void writePngRadiance(const std::filesystem::path& path, uint32_t width, uint32_t height,
                      const std::vector<float>& pixels);
// Diverging colormap symmetric about zero (blue negative, white zero, red positive); `scale`
// is the magnitude that maps to full colour (returned so callers can print it).
float writePngDiverging(const std::filesystem::path& path, uint32_t width, uint32_t height,
                        const std::vector<float>& pixels);
// A strip of small tiles, one per layer (transient stacks), sharing one exposure: layers larger
// than 128 pixels are box-filtered down, smaller than 64 magnified by a whole factor.
void writePngContactSheet(const std::filesystem::path& path, const ImageSet& images);

// NumPy .npy of shape (H, W, T) float32, T = number of layers.
void writeNpy(const std::filesystem::path& path, const ImageSet& images);

// Writes bytes atomically (temp file + rename). Throws vktg::Error naming the path on failure.
void writeFileAtomic(const std::filesystem::path& path, const std::string& bytes);
// Throws if `output` is the same file as any of `inputs` (refuse to overwrite an input), or if
// its directory does not exist / is not writable.
void checkOutputPath(const std::filesystem::path& output, const std::vector<std::filesystem::path>& inputs);

}  // namespace vktg
