// What an experiment's targets need at run time: the scene seen from a target, the checks of its
// image (read from an EXR or synthesised), and the parameter error against the truth.
#include <cmath>

#include "opt/experiment.h"
#include "opt/experiment_capture.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// The field that names a target's image: its "image", or its "capture" file.
std::string imageField(const Target& target) {
  return "targets[" + std::to_string(target.entry) + (target.capture ? "].capture" : "].image");
}

std::string describeShape(uint32_t width, uint32_t height, size_t layers) {
  return std::to_string(width) + "x" + std::to_string(height) + " with " + std::to_string(layers) +
         (layers == 1 ? " layer" : " layers");
}

std::string describeImage(const Target& target) {
  return target.synthesize ? "the synthesised image" : target.image.string();
}

[[noreturn]] void failTarget(const Experiment& experiment, size_t target, const std::string& problem) {
  const Target& t = experiment.targets[target];
  fail(experiment.source.string(), imageField(t), "target \"" + t.name + "\": " + problem);
}

// The size of a scan's whole image (laid out as `vktg render --scan` writes it) and of one point's.
struct ScanLayout {
  uint32_t width, height, pointWidth, pointHeight;
};

ScanLayout scanLayout(const Experiment& experiment, const Target& t) {
  const Camera& camera = experiment.scene.camera;
  const glm::uvec2 pixels = imagePixels(camera);
  if (camera.type == CameraType::PointSensor) return {t.scanColumns, t.scanRows, 1, 1};
  return {pixels.x, pixels.y * t.scanViews, pixels.x, pixels.y};
}

// View `t.scanView`'s image out of the whole scan's, after checking the whole image's size against
// the scan, the camera and the gate.
ImageSet scanPointImage(const Experiment& experiment, size_t target, const ImageSet& whole) {
  const Target& t = experiment.targets[target];
  const ScanLayout layout = scanLayout(experiment, t);
  if (whole.width != layout.width || whole.height != layout.height || whole.layers.size() != t.gate.layers())
    failTarget(experiment, target,
               t.image.string() + " is " + describeShape(whole.width, whole.height, whole.layers.size()) +
                   ", but its scan of " + std::to_string(t.scanViews) + " views and its gate render " +
                   describeShape(layout.width, layout.height, t.gate.layers()) + " (gate: " + t.gate.describe() + ")");
  ImageSet point{layout.pointWidth, layout.pointHeight, {}};
  const size_t pixels = size_t(point.width) * point.height, first = size_t(*t.scanView) * pixels;
  for (const ImageLayer& layer : whole.layers)
    point.layers.push_back({layer.name, std::vector<float>(layer.pixels.begin() + first, layer.pixels.begin() + first + pixels)});
  return point;
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

namespace {

// The file of a target's "targets" entry (a scan's: the whole scan's image).
ImageSet readTargetFile(const Experiment& experiment, size_t target) {
  const Target& t = experiment.targets.at(target);
  if (t.synthesize) failTarget(experiment, target, "is synthesised by rendering: it has no file to read");
  if (t.capture) return captureTargetImage(t.image, experiment.source.string(), imageField(t));
  try {
    return readExr(t.image);
  } catch (const Error& e) {
    fail(experiment.source.string(), imageField(t), e.what());
  }
}

// The target's image out of its entry's file, checked against its view and gate.
ImageSet checkedTargetImage(const Experiment& experiment, size_t target, const ImageSet& file) {
  const Target& t = experiment.targets.at(target);
  ImageSet image = t.scanView ? scanPointImage(experiment, target, file) : file;
  // A view moves the camera but never changes its resolution.
  const Camera& camera = experiment.scene.camera;
  checkTargetImageSize(experiment, target, image, imagePixels(camera).x, imagePixels(camera).y, t.gate.layers());
  checkTargetImageFinite(experiment, target, image);
  return image;
}

}  // namespace

ImageSet loadTargetImage(const Experiment& experiment, size_t target) {
  return checkedTargetImage(experiment, target, readTargetFile(experiment, target));
}

std::vector<ImageSet> loadTargetImages(const Experiment& experiment, const TargetEntry& entry) {
  const ImageSet file = readTargetFile(experiment, entry.targets.front());
  std::vector<ImageSet> images;
  for (size_t t : entry.targets) images.push_back(checkedTargetImage(experiment, t, file));
  return images;
}

std::vector<TargetEntry> targetEntries(const Experiment& experiment) {
  std::vector<TargetEntry> entries;
  for (size_t t = 0; t < experiment.targets.size(); ++t) {
    const Target& target = experiment.targets[t];
    // A scan's points are consecutive and share their entry; any other target is an entry alone.
    const bool samePoint = t > 0 && target.scanView && experiment.targets[t - 1].scanView &&
                           experiment.targets[t - 1].entry == target.entry;
    if (!samePoint) entries.push_back({target.entryName, {}, target.scanView.has_value()});
    entries.back().targets.push_back(t);
  }
  return entries;
}

ImageSet joinScanImages(const Experiment& experiment, const TargetEntry& entry, const std::vector<ImageSet>& images) {
  const ScanLayout layout = scanLayout(experiment, experiment.targets.at(entry.targets.front()));
  ImageSet whole{layout.width, layout.height, {}};
  for (size_t t : entry.targets) {
    const ImageSet& point = images.at(t);
    if (whole.layers.empty())
      for (const ImageLayer& layer : point.layers) whole.layers.push_back({layer.name, {}});
    for (size_t l = 0; l < point.layers.size(); ++l)
      whole.layers[l].pixels.insert(whole.layers[l].pixels.end(), point.layers[l].pixels.begin(), point.layers[l].pixels.end());
  }
  return whole;
}

std::vector<ImageSet> splitScanImage(const Experiment& experiment, const TargetEntry& entry, const ImageSet& whole,
                                     const std::string& source) {
  const Target& first = experiment.targets.at(entry.targets.front());
  const ScanLayout layout = scanLayout(experiment, first);
  if (whole.width != layout.width || whole.height != layout.height || whole.layers.size() != first.gate.layers())
    fail(source, "", "is " + describeShape(whole.width, whole.height, whole.layers.size()) + ", but the scan \"" +
                         entry.name + "\" renders " + describeShape(layout.width, layout.height, first.gate.layers()));
  std::vector<ImageSet> points;
  for (size_t t : entry.targets) points.push_back(scanPointImage(experiment, t, whole));
  return points;
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
