// What an experiment's targets need at run time: the scene seen from a target, the checks of its
// image (read from an EXR or synthesised), and the parameter error against the truth.
#include <cmath>

#include "opt/experiment.h"
#include "vktg/error.h"

namespace vktg {
namespace {

std::string imageField(size_t target) { return "targets[" + std::to_string(target) + "].image"; }

std::string describeShape(uint32_t width, uint32_t height, size_t layers) {
  return std::to_string(width) + "x" + std::to_string(height) + " with " + std::to_string(layers) +
         (layers == 1 ? " layer" : " layers");
}

std::string describeImage(const Target& target) {
  return target.synthesize ? "the synthesised image" : target.image.string();
}

[[noreturn]] void failTarget(const Experiment& experiment, size_t target, const std::string& problem) {
  fail(experiment.source.string(), imageField(target), "target \"" + experiment.targets[target].name + "\": " + problem);
}

}  // namespace

Scene sceneForTarget(const Scene& scene, const Target& target) {
  Scene out = scene;
  const SceneView& view = target.view;
  out.camera = cameraSeenFrom(scene.camera, view);
  for (const auto& [light, position] : view.lightPositions) {
    if (light >= out.pointLights.size())
      fail(scene.source.string(), "target \"" + target.name + "\"", "view moves point light " + std::to_string(light) +
                                                                      " but the scene has " +
                                                                      std::to_string(out.pointLights.size()));
    out.pointLights[light].position = position;
  }
  out.gate = target.gate;
  return out;
}

void checkTargetImageSize(const Experiment& experiment, size_t target, const ImageSet& image, uint32_t width,
                          uint32_t height, uint32_t layers) {
  const Target& t = experiment.targets.at(target);
  if (image.width != width || image.height != height || image.layers.size() != layers) {
    std::string problem = describeImage(t) + " is " + describeShape(image.width, image.height, image.layers.size()) +
                          ", but its view and gate render " + describeShape(width, height, layers);
    if (image.layers.size() != layers) problem += " (gate: " + t.gate.describe() + ")";
    failTarget(experiment, target, problem);
  }
  for (const ImageLayer& layer : image.layers)
    if (layer.pixels.size() != size_t(width) * height)
      failTarget(experiment, target,
                 describeImage(t) + ": layer \"" + layer.name + "\" holds " + std::to_string(layer.pixels.size()) +
                     " pixels, not " + std::to_string(size_t(width) * height));
}

void checkTargetImageFinite(const Experiment& experiment, size_t target, const ImageSet& image) {
  size_t count = 0;
  std::string first;
  for (const ImageLayer& layer : image.layers)
    for (size_t i = 0; i < layer.pixels.size(); ++i) {
      if (std::isfinite(layer.pixels[i])) continue;
      if (count++ == 0 && image.width > 0)
        first = std::to_string(layer.pixels[i]) + " at x " + std::to_string(i % image.width) + ", y " +
                std::to_string(i / image.width) + (layer.name.empty() ? "" : " of layer \"" + layer.name + "\"");
    }
  if (count > 0)
    failTarget(experiment, target,
               describeImage(experiment.targets.at(target)) + " holds " + std::to_string(count) +
                   " non-finite pixel(s), the first " + first + ": a loss against it would be NaN");
}

ImageSet loadTargetImage(const Experiment& experiment, size_t target) {
  const Target& t = experiment.targets.at(target);
  if (t.synthesize) failTarget(experiment, target, "is synthesised by rendering: it has no file to read");
  ImageSet image;
  try {
    image = readExr(t.image);
  } catch (const Error& e) {
    fail(experiment.source.string(), imageField(target), e.what());
  }
  // A view moves the camera but never changes its resolution.
  const Camera& camera = experiment.scene.camera;
  checkTargetImageSize(experiment, target, image, imagePixels(camera).x, imagePixels(camera).y, t.gate.layers());
  checkTargetImageFinite(experiment, target, image);
  return image;
}

std::optional<double> parameterError(const std::vector<ExperimentParameter>& parameters, const std::vector<double>& theta) {
  if (theta.size() != parameters.size())
    fail("", "parameter error", "got " + std::to_string(theta.size()) + " values for " +
                                    std::to_string(parameters.size()) + " parameters");
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (!parameters[i].truth) continue;
    const double error = theta[i] - *parameters[i].truth;
    sum += error * error;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return std::sqrt(sum / double(count));
}

}  // namespace vktg
