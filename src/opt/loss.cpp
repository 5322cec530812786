// Image losses and their adjoint images (loss.h). Sums run in double precision over float pixels.
#include "opt/loss.h"

#include <cmath>

#include "vktg/error.h"

namespace vktg {
namespace {

void requireSameLayout(const ImageSet& rendered, const ImageSet& target) {
  const auto describe = [](const ImageSet& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height) + " with " +
           std::to_string(image.layers.size()) + " layer(s)";
  };
  bool same = rendered.width == target.width && rendered.height == target.height &&
              rendered.layers.size() == target.layers.size() && !rendered.layers.empty();
  const size_t pixels = size_t(rendered.width) * rendered.height;
  for (size_t l = 0; same && l < rendered.layers.size(); ++l)
    same = rendered.layers[l].pixels.size() == pixels && target.layers[l].pixels.size() == pixels;
  if (!same)
    fail("", "loss", "the rendered image (" + describe(rendered) + ") and the target (" + describe(target) +
                         ") differ in size or layers, or a layer has the wrong pixel count");
}

// The scale of the relative L2 denominator: (epsilon * mean |T|)^2.
double relativeFloor(double epsilon, const ImageSet& target, double count) {
  double sum = 0;
  for (const ImageLayer& layer : target.layers)
    for (float t : layer.pixels) sum += std::abs(double(t));
  const double floor = epsilon * sum / count;
  if (!(floor > 0))
    fail("", "loss", "relative_l2 needs a target with some non-zero pixel (every pixel of the target is 0)");
  return floor * floor;
}

}  // namespace

double imageLoss(const LossSpec& spec, const ImageSet& rendered, const ImageSet& target, double weight,
                 ImageSet* adjoint) {
  requireSameLayout(rendered, target);
  const double count = double(rendered.layers.size()) * double(rendered.width) * double(rendered.height);
  const double scale = weight / count;
  const double floor = spec.type == LossType::RelativeL2 ? relativeFloor(spec.epsilon, target, count) : 0.0;
  if (adjoint) {
    adjoint->width = rendered.width;
    adjoint->height = rendered.height;
    adjoint->layers.resize(rendered.layers.size());
  }
  double sum = 0;
  for (size_t l = 0; l < rendered.layers.size(); ++l) {
    const std::vector<float>& image = rendered.layers[l].pixels;
    const std::vector<float>& reference = target.layers[l].pixels;
    std::vector<float>* derivative = nullptr;
    if (adjoint) {
      adjoint->layers[l].name = rendered.layers[l].name;
      derivative = &adjoint->layers[l].pixels;
      derivative->resize(image.size());
    }
    for (size_t i = 0; i < image.size(); ++i) {
      const double difference = double(image[i]) - double(reference[i]);
      double value = 0, slope = 0;  // per-pixel loss and its derivative in I
      switch (spec.type) {
        case LossType::L2:
          value = difference * difference;
          slope = 2 * difference;
          break;
        case LossType::L1:
          value = std::abs(difference);
          slope = difference > 0 ? 1.0 : difference < 0 ? -1.0 : 0.0;
          break;
        case LossType::RelativeL2: {
          const double denominator = double(reference[i]) * double(reference[i]) + floor;
          value = difference * difference / denominator;
          slope = 2 * difference / denominator;
          break;
        }
      }
      sum += value;
      if (derivative) (*derivative)[i] = float(scale * slope);
    }
  }
  return scale * sum;
}

}  // namespace vktg
