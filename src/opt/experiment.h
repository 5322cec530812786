// Experiment files for `vktg optimize` (docs/optimize.md): which scene, which parameters to recover
// from which time-of-flight images, with which loss, optimiser, constraints and sample budgets.
// Parsing is strict like the scene format: every error names the file, the JSON path of the field
// and the problem.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene_view.h"
#include "vktg/gate.h"
#include "vktg/image_io.h"
#include "vktg/scene.h"

namespace vktg {

// One optimised scene parameter (a wildcard in the file expands to several, in scene order).
// θ is absolute: 0 is the scene as written, as for `vktg grad` and `vktg fd`.
struct ExperimentParameter {
  std::string name;
  uint32_t sceneIndex = 0;          // index in Scene::parameters
  double initial = 0;               // θ at iteration 0
  std::optional<double> truth;      // θ of the scene the targets show, when known
  std::string group = "default";    // learning-rate group
  ParameterRange range;             // projection after each step: the kind's valid range ∩ "range"
};

// Where a target was seen from: overrides of the scene's camera pose and point-light positions.
struct Target {
  std::string name;                 // unique, letters, digits, '_', '-', '.'; names images and log columns
  SceneView view;                   // where the camera and the point lights are for this target
  Gate gate;                        // default: the scene's gate; may be a transient stack
  double weight = 1;                // factor on this target's loss
  std::filesystem::path image;      // an EXR whose size and layers match the view and gate ...
  bool synthesize = false;          // ... or rendered at the truth with independent random numbers
  bool capture = false;             // ... or `image` is an NLOS capture file (experiment_capture.h)
  uint32_t synthesizeSpp = 4096;
  uint32_t synthesizeSeed = 0x5eed;  // the parser's default: 0x5eed + the target's index
  // The "targets" entry this target comes from: a "scan" or "capture" entry makes one target per
  // scan point.
  size_t entry = 0;
  std::string entryName;            // that entry's name: names its log column and initial image
  // A scan point's target: its view of the scan, of scanViews, whose image is laid out as `vktg
  // render --scan` writes it (scanColumns x scanRows pixels at a point sensor; the views' images
  // one below the other behind a pinhole); `image` is that whole image.
  std::optional<uint32_t> scanView;
  uint32_t scanViews = 0, scanColumns = 0, scanRows = 0;
};

enum class LossType { L2, L1, RelativeL2 };

struct LossSpec {
  LossType type = LossType::L2;
  double epsilon = 1e-2;            // relative L2: keeps the denominator away from 0 (loss.h)
};

enum class OptimizerType { Adam, Sgd };
enum class ScheduleType { Constant, Exponential, Step };

struct ScheduleSpec {
  ScheduleType type = ScheduleType::Constant;
  double decay = 1.0;               // exponential: lr * decay^iteration; step: lr * decay^(iteration / every)
  uint32_t every = 1;               // step
  // Any type: the first `warmup` steps scale the rate by (step + 1) / warmup, so that Adam's moments
  // have averaged several noisy gradients before it takes full-sized steps.
  uint32_t warmup = 0;
};

struct OptimizerSpec {
  OptimizerType type = OptimizerType::Adam;
  double learningRate = 1e-2;       // of the group "default"
  std::vector<std::pair<std::string, double>> groupRates;  // other groups: name -> learning rate
  double beta1 = 0.9, beta2 = 0.999, epsilon = 1e-8;       // Adam
  // Adam: divide by the largest second moment of the parameter's learning-rate group instead of its
  // own (Nicolet et al. 2021's "uniform Adam"), so that a group's step keeps its gradient's shape.
  bool uniform = false;
  double momentum = 0.9;            // SGD
  ScheduleSpec schedule;
};

// Laplacian smoothness of a shape's vertex positions (heightfields, meshes).
struct RegularizerSpec {
  uint32_t shape = 0;               // Scene::shapes index
  double weight = 0;
};

// "Large steps" (Nicolet et al. 2021): the gradient of parameters that each displace one vertex of
// `shape` is replaced by (I + lambda L)^-1 times it, L the uniform Laplacian of the shape's mesh.
struct PreconditionerSpec {
  uint32_t shape = 0;
  double lambda = 0;
};

// Samples per pixel per iteration for each term, and which terms run.
struct BudgetSpec {
  uint32_t sppPrimal = 16;          // the render the loss and its adjoint image come from
  uint32_t sppInterior = 16;
  // The interior term in this many chained passes of sppInterior / interiorPasses samples, each
  // weighted by the adjoint of the render and the passes before it (host/gradient.h AdjointChain):
  // the loss then comes from sppPrimal + sppInterior samples, and sppPrimal can be a fraction of
  // sppInterior without a noisier adjoint.
  uint32_t interiorPasses = 1;
  // The other terms' samples per pixel on average (fractions allowed: loss gradients spread fewer
  // samples than pixels over the image).
  double sppEdge = 16;
  double sppBoundary = 16;
  // The path-length boundary's connections from the camera (splatted); left out, as sppBoundary
  // (its count or "auto").
  double sppBoundaryCamera = 16;
  // "auto": the term's samples come from a pilot at the first iteration (host/term_pilot.h).
  bool sppEdgeAuto = false, sppBoundaryAuto = false, sppBoundaryCameraAuto = false;
  bool interior = true, edge = true, pathLength = true;  // the planner still drops terms that cannot contribute
  std::string antithetic = "auto";  // auto | on | off
  NeeMode nee = NeeMode::Auto;
  uint32_t maxDepth = 0;            // 0: the scene's
  // The gradient: adjoint renders of the three terms, or central differences of the loss with
  // step finiteDifferenceStep (in each parameter's units), the baseline the experiments compare with.
  bool finiteDifferences = false;
  double finiteDifferenceStep = 0;
};

struct StopSpec {
  uint32_t iterations = 100;
  std::optional<double> lossBelow;
  std::optional<double> parameterErrorBelow;  // RMS of (θ - truth) over parameters with a truth
  std::optional<double> seconds;
};

struct Experiment {
  std::filesystem::path source;     // the experiment file
  std::string text;                 // its contents (copied into the run directory)
  std::filesystem::path scenePath;
  SceneDefines sceneDefines;        // a Mitsuba XML scene's $name values: the file's "defines", then -D
  Scene scene;
  std::vector<ExperimentParameter> parameters;
  std::vector<Target> targets;
  LossSpec loss;
  OptimizerSpec optimizer;
  std::vector<RegularizerSpec> regularizers;
  std::optional<PreconditionerSpec> preconditioner;
  BudgetSpec budget;
  StopSpec stop;
  uint32_t checkpointEvery = 10;    // iterations
  uint32_t imagesEvery = 10;        // iterations between image strips
  uint32_t seed = 0;                // random numbers of iteration i are keyed by (seed, i)
};

// `defines` (`vktg optimize -D`) override the "defines" of the experiment's "scene".
Experiment loadExperiment(const std::filesystem::path& path, const SceneDefines& defines = {});
Experiment parseExperimentJson(const std::string& text, const std::string& file, const std::filesystem::path& baseDir,
                               const SceneDefines& defines = {});

// The scene seen from a target: its camera pose and point lights moved as the view says, and the
// target's gate.
Scene sceneForTarget(const Scene& scene, const Target& target);

// Checks of a target image (read from its EXR or synthesised). Each throws vktg::Error naming the
// experiment file, the target's field ("targets[1].image"), the target and the problem.
// `image` must have width x height pixels in `layers` layers:
void checkTargetImageSize(const Experiment& experiment, size_t target, const ImageSet& image, uint32_t width,
                          uint32_t height, uint32_t layers);
// ... and no NaN or infinite pixel:
void checkTargetImageFinite(const Experiment& experiment, size_t target, const ImageSet& image);
// Reads a target's EXR (Target::image) and checks it against the camera of sceneForTarget and the
// layers of the target's gate.
ImageSet loadTargetImage(const Experiment& experiment, size_t target);

// The "targets" entries in file order, each with its targets (a scan's: one per point, in scan order).
struct TargetEntry {
  std::string name;
  std::vector<size_t> targets;
  bool scan = false;
};
std::vector<TargetEntry> targetEntries(const Experiment& experiment);

// A scan entry's point images as one, laid out as `vktg render --scan` writes it (at a point sensor
// the scan grid, else the views one below the other): `images` is indexed by target, as the
// experiment's targets are, and each layer holds the points' pixels in scan order. splitScanImage
// undoes it, returning the entry's point images in its order; it throws vktg::Error naming `source`
// when `whole` does not hold the entry's points.
ImageSet joinScanImages(const Experiment& experiment, const TargetEntry& entry, const std::vector<ImageSet>& images);
std::vector<ImageSet> splitScanImage(const Experiment& experiment, const TargetEntry& entry, const ImageSet& whole,
                                     const std::string& source);

// loadTargetImage for every target of an entry whose image is a file, reading the file once.
std::vector<ImageSet> loadTargetImages(const Experiment& experiment, const TargetEntry& entry);

// RMS of θ - truth over the parameters that have a truth; nullopt when none has one.
std::optional<double> parameterError(const std::vector<ExperimentParameter>& parameters, const std::vector<double>& theta);

}  // namespace vktg
