// The planner: which estimator and which shader specialisations a scene needs, and why
// (`--explain` prints the reasons). Simulate only what the scene calls for.
#pragma once
#include <string>
#include <vector>

#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg {

// What one render sees besides the device-resident scene: the camera, the gate and the render
// settings (a target of an optimisation may override the scene's), and the file they came from.
struct RenderSetup {
  Camera camera;
  Gate gate;
  RenderSettings settings;
  std::string source;
  float pathOffset = 0.0f;  // optical path outside the scene, in metres, added before the gate (SceneView)

  static RenderSetup of(const Scene& scene) { return {scene.camera, scene.gate, scene.render, scene.source.string(), 0.0f}; }
};

// How an ellipsoidal connection chooses the triangle it lands on (shaders/lib/ellipsoid.glsl).
enum class EllipsoidSelection : uint32_t {
  Auto,       // the planner's choice
  Descend,    // stochastic BVH descent: cost logarithmic in the triangle count
  Enumerate,  // every triangle the shell meets, by arc length: the reference
};

struct RenderPlan {
  NeeMode nee = NeeMode::Standard;    // Standard or Ellipsoidal after planning
  EllipsoidSelection ellipsoidSelection = EllipsoidSelection::Descend;  // Descend or Enumerate after planning
  uint32_t firstEllipsoidVertex = 1;  // 0 at a point sensor, 1 behind a pinhole
  uint32_t layers = 1;
  double gateWidth = 0;               // metres
  double pathSpread = 0;              // metres: the scene diagonal, the spread of path lengths
  std::vector<std::string> reasons;
};

// A gate narrower than this fraction of the scene's path-length spread gets ellipsoidal NEE: a
// standard path tracer would land almost every sample outside such a gate.
inline constexpr double kEllipsoidalGateFraction = 0.05;

// The first path vertex an ellipsoidal connection can start from: the point sensor itself, or the
// first hit behind a pinhole (whose pixel fixes it).
inline uint32_t firstEllipsoidVertex(CameraType camera) { return camera == CameraType::PointSensor ? 0 : 1; }

// `requested` and `selection` override the scene's setting and the planner's choice unless Auto.
// `neeNotes` say how `requested` was measured (they replace "requested"), or, with Auto, why no
// measurement was made (they follow the rule's reason). Throws vktg::Error for impossible requests
// (ellipsoidal NEE with a steady gate).
RenderPlan planRender(const RenderSetup& setup, const PreparedScene& prepared, NeeMode requested,
                      EllipsoidSelection selection = EllipsoidSelection::Auto,
                      const std::vector<std::string>& neeNotes = {});
std::string explainPlan(const RenderPlan& plan);
// printf into a reason line (at most 511 characters).
std::string formatReason(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
const char* neeModeName(NeeMode mode);
const char* ellipsoidSelectionName(EllipsoidSelection selection);

}  // namespace vktg
