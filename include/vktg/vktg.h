// vktg as a library: time-gated renders of a scene and their derivatives with respect to its
// parameters, on any Vulkan device (a GPU, or the CPU through lavapipe). No Vulkan types: a
// Context owns the device, a Model is a scene and the values of its parameters, and the functions
// below render it, differentiate it forward (derivative images per parameter) or backward (given
// d loss / d image for every view, d loss / d θ for every parameter, at a cost that does not grow
// with the number of parameters). Errors are vktg::Error with the message the command line prints
// ("file: field: problem"); a render interrupted by SIGINT or SIGTERM throws vktg::Interrupted.
//
//   vktg::Context context;                                  // a GPU, else lavapipe
//   vktg::Model model = vktg::Model::load("scenes/occluder_shadow.json");
//   vktg::Rendered image = vktg::render(context, model);
//   vktg::Derivatives d = vktg::derivatives(context, model, {"occluder_x"});
//   std::vector<double> dl = vktg::renderBackward(context, model, {"occluder_x"}, {dLossDImage});
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vktg/error.h"
#include "vktg/gate.h"
#include "vktg/image_io.h"
#include "vktg/scene.h"

namespace vktg {

// Which device and how much of it (the command line's --device and --mem).
struct DeviceOptions {
  // "": the best available (a GPU, else lavapipe); "gpu": the best GPU; a number: the index `vktg
  // info` lists; anything else: a substring of the device's name ("llvmpipe").
  std::string device;
  bool validation = false;    // the Khronos validation layer; its messages are counted (validationMessages)
  uint64_t memoryBudget = 0;  // bytes for film and wavefront state; 0: the device's default
};

class Context {
 public:
  explicit Context(const DeviceOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  std::string deviceName() const;
  bool cpuDevice() const;
  uint64_t memoryBudget() const;
  size_t validationMessages() const;  // 0 unless DeviceOptions::validation
  // The device and the renderer that keeps its pipelines and buffers from one call to the next
  // (src/api/context_impl.h; opaque here).
  struct Impl;
  Impl& impl() { return *m_impl; }

 private:
  std::unique_ptr<Impl> m_impl;
};

// A scene and a value θ_k for each of its parameters (0 as the file wrote it). The scene's own
// settings (camera, gate, samples, seed) are its defaults for every render.
class Model {
 public:
  static Model load(const std::filesystem::path& file);  // a .json scene or a .gltf/.glb
  // Scene JSON text; `name` names it in errors and `baseDir` resolves the files it refers to.
  static Model parse(const std::string& json, const std::string& name = "<string>",
                     const std::filesystem::path& baseDir = std::filesystem::current_path());
  static Model builtIn();  // the command line's default scene

  const Scene& scene() const { return m_scene; }
  Scene& scene() { return m_scene; }
  std::vector<std::string> parameterNames() const;
  // The names a comma-separated list with wildcards ("h*,light_x") selects, in the scene's order.
  std::vector<std::string> select(const std::string& list) const;
  double value(const std::string& name) const;
  void setValue(const std::string& name, double theta);  // θ must be finite
  std::vector<double> values(const std::vector<std::string>& names) const;
  void setValues(const std::vector<std::string>& names, const std::vector<double>& theta);
  // The scene at the current values, with θ = 0 there (what every render of the model renders).
  Scene current() const;

 private:
  explicit Model(Scene scene);
  Scene m_scene;
  std::vector<double> m_theta;  // per scene().parameters
};

// One view of a render of several: a camera pose, its random numbers and where it places point
// lights (by their index in scene().pointLights). Its camera type and image size are the scene's.
struct View {
  Camera camera;
  uint32_t seed = 0;
  std::vector<std::pair<uint32_t, glm::vec3>> lightPositions;
  // Optical path outside the scene (metres) that every path of the view counts before the gate:
  // a capture device's legs to and from the relay wall.
  float pathOffset = 0.0f;
};

// The views of a scan file (a relay-wall grid or a list of views; docs/scene-format.md, Scans),
// each with the seed `vktg render --scan` gives it.
std::vector<View> scanViews(const Model& model, const std::filesystem::path& scanFile);

// What a render changes from the scene's settings (the command line's options of the same names).
struct RenderRequest {
  std::optional<Gate> gate;
  std::optional<uint32_t> spp, seed, maxDepth;
  std::optional<std::pair<uint32_t, uint32_t>> resolution;  // perspective cameras
  NeeMode nee = NeeMode::Auto;  // Auto: the scene's, else the planner's (with the pilot, as `vktg render`)
  bool pilot = true;            // let a timed pilot choose NEE where that pays (`--pilot auto`)
  std::vector<View> views;      // empty: the scene's camera, one image
  std::function<void(double)> progress;  // fraction done, after every batch
};

struct Rendered {
  std::vector<ImageSet> images;     // per view (one without views): a layer per gate layer
  std::vector<ImageSet> variances;  // of each pixel's mean
  std::string plan;                 // what the planner chose and why (`--explain`)
  uint64_t nonFinite = 0;           // samples dropped as NaN or infinite (0 in a sound render)
  double seconds = 0;
};

Rendered render(Context& context, const Model& model, const RenderRequest& request = {});

// The derivative terms (docs/theory.md §3): which run, and their samples.
struct GradRequest : RenderRequest {
  bool interior = true, edge = true, pathLength = true;  // the planner drops those that cannot contribute
  double sppEdge = 0, sppBoundary = 0, sppBoundaryCamera = 0;  // 0: spp (`--spp-edge` etc.)
  std::optional<bool> antithetic;  // unset: for near-delta gates
};

struct Derivatives {
  std::vector<std::string> parameters;
  ImageSet image;  // the image itself (views stacked one below the other, as the render holds them)
  // Per parameter: d image / d θ, a layer per gate layer; the sum of the terms, then each term.
  std::vector<ImageSet> total, interior, edge, pathLength;
  std::vector<ImageSet> totalVariance;
  std::vector<std::string> plan;  // the gradient planner's reasons
};

// Forward mode: derivative images of every parameter named (a pass per term and per block of four
// parameters). With views, their images lie one below the other.
Derivatives derivatives(Context& context, const Model& model, const std::vector<std::string>& parameters,
                        const GradRequest& request = {});

// The adjoint pass: given d loss / d I for every view's image (`adjoints`, one per view, or one for
// the scene's camera; the shapes of render's images), d loss / d θ for every parameter named. Its
// random numbers are its own (request.seed and the views' seeds): pass d loss / d I from an image
// rendered with other seeds, as `vktg optimize` does, or the gradient of a loss that is not linear
// in the image is biased.
std::vector<double> renderBackward(Context& context, const Model& model, const std::vector<std::string>& parameters,
                                   const std::vector<ImageSet>& adjoints, const GradRequest& request = {});

// Asks the renders under way to stop after their current batch, as SIGINT does (they throw
// vktg::Interrupted), and forgets such a request (a binding's Ctrl-C; the command line's signals).
void requestInterrupt(int signal);
void clearInterrupt();

}  // namespace vktg
