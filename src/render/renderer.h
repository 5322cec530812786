// The renderer: a wavefront path tracer over batches of paths sized from a memory budget, on a
// device-resident scene (DeviceScene). One command buffer per batch runs every bounce (indirect
// dispatches from queue counters). A render computes one of the terms of THEORY.md §3 (or the
// image alone), either as forward-mode derivative images (lanes) or, given an adjoint image, as the
// gradient of a loss accumulated on the device (AdjointTarget, THEORY.md §7).
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/adjoint.h"
#include "render/device_scene.h"
#include "render/pass_table.h"
#include "render/planner.h"
#include "vk/vk_context.h"
#include "vktg/image_io.h"
#include "vktg/parameters.h"
#include "vktg/scene.h"

namespace vktg {

// The adjoint form of a render: instead of derivative images, every sample adds
// (d loss / d I of its pixel) × (its contribution's derivative) into `gradient`.
struct AdjointTarget {
  const Buffer* image = nullptr;  // d loss / d I: float[layer * pixels + pixel] of this render's camera and gate
  GradientAccumulator* gradient = nullptr;
  double scale = 1;               // accumulators add round(value * scale); a power of two
  uint32_t targets = 0;           // kAdjoint* bits: what to differentiate
  // The first render of a gradient clears the accumulators and the last copies them for the host,
  // each with its own commands (GradientAccumulator::recordClear, recordCopyBack).
  bool clearFirst = false, copyBack = false;
  // Where the host wrote the image when it cannot map `image`'s memory: this render's first commands
  // copy it over (the first render of each image's views).
  const Buffer* imageStaging = nullptr;
  // The interior term's render also returns the image of its paths (RenderResult::mean), as a
  // plain render with the same seed and samples would: a chained gradient's later passes weight
  // by an adjoint image that includes it (lossGradient, AdjointChain).
  bool renderImage = false;
};

struct RenderOptions {
  NeeMode nee = NeeMode::Auto;              // overrides the scene's render.nee unless Auto
  std::vector<std::string> neeNotes;        // how `nee` was chosen, for the plan (see planRender)
  EllipsoidSelection ellipsoidSelection = EllipsoidSelection::Auto;  // overrides the planner's unless Auto
  uint64_t memoryBudget = 0;  // bytes for wavefront state + film (`--mem`); 0: the device's default (memory_preflight.h)
  bool gateCutoff = true;                   // end paths whose length passed the gate (bench compares)
  bool profile = false;                     // time every pass (RenderResult::passMilliseconds); GPU
                                            // timestamps cost a few ms per render on lavapipe
  std::function<void(double)> progress;     // fraction done, after every batch
  // Non-empty: the derivative variants of the passes also compute d image / d θ for these
  // parameters (forward mode), at most kMaxDerivativeLanes at once.
  std::vector<ParameterBinding> derivativeLanes;
  // Or the adjoint form (no lanes; no image unless AdjointTarget::renderImage).
  const AdjointTarget* adjoint = nullptr;
  // Which term the render computes (plan/terms.h; its passes: render/pass_table.h): the image and
  // the interior term by default. A boundary term's render leaves the image channel zero. Edge:
  // settings.spp edge samples per pixel on average (sample_edges), splatted into the pixels their
  // camera connections reach; PathLengthFromCamera: that term's share of the paths the per-pixel
  // pass cannot place on a jump, camera -> x1 -> light behind a pinhole and camera -> emitter
  // (connections from the camera, splatted; settings.spp samples per pixel on average);
  // InteriorAndPathLength (adjoint renders): both from one trace of the paths, the sum the two
  // renders give with the same seed, since both draw the same random numbers.
  Term term = Term::Interior;
  // Antithetic pairs (THEORY.md §5): ellipsoidal connections at s and 2 mu - s (gaussian gates);
  // in the path-length-boundary term, connections to both jumps of a box or truncated gaussian.
  bool antithetic = false;
  // > 0: the samples per pixel, on average, in place of settings.spp, and it may be fractional: in
  // splatted renders (edges, connections from the camera) any number of samples, in per-pixel
  // adjoint renders round(samplesPerPixel x pixels) paths spread over the pixels from an offset the
  // seed draws, so that every pixel is reached as often on average (the term pilot's allocations
  // below one sample per pixel). Contributions are weighted by 1 / this mean either way.
  double samplesPerPixel = 0;
};

inline constexpr uint32_t kMaxDerivativeLanes = 4;

// One view of a render that holds several (the scan points of a capture, the targets of an
// optimisation): its camera pose, its random numbers and the point lights it moves. The camera's
// type and image size are the render's. Each view gets the rows of one tall image that it would get
// rendered alone (splitViews), and a batch of views costs one render's passes instead of one per view.
struct RenderView {
  Camera camera;
  uint32_t seed = 0;
  std::vector<std::pair<uint32_t, glm::vec3>> lightPositions;  // point lights moved for this view
  float pathOffset = 0.0f;  // optical path outside the scene added before the gate (SceneView)
};

// The image of each view of a render of `views` views (RenderView), from the rows it was given.
std::vector<ImageSet> splitViews(const ImageSet& stacked, size_t views);

struct RenderStats {
  uint64_t paths = 0;
  uint64_t extensionRays = 0, shadowRays = 0;
  uint64_t endedByGate = 0, endedByRoulette = 0, endedByDepth = 0;
  uint64_t nonFinite = 0;
  uint64_t ellipsoidQueries = 0, ellipsoidEmpty = 0;
  // Edge term: silhouette-capable edges, samples whose direction made their edge a silhouette,
  // and of those the ones whose boundary segment reached the camera.
  uint64_t silhouetteEdges = 0, edgeSilhouettes = 0, edgeConnected = 0;
  uint64_t gradientOverflows = 0;  // adjoint scatters beyond the accumulators' range
  uint32_t batches = 0, batchSize = 0;
  uint64_t deviceBytes = 0;  // scene + wavefront + film
  uint32_t bufferChunks = 0; // the most chunks a chunked buffer (triangles, BVH nodes, film) took
  bool sceneTexels = false;  // the traversal loaded triangles and BVH nodes through texel buffers
  bool wideBvh = false;      // the closest- and any-hit traversals ran over the 4-wide BVH
  bool waveTexels = false;   // intersect_closest and shade loaded path states and hits through them
  double seconds = 0;        // wall time of the batches (excludes pipeline creation)
};

struct RenderResult {
  ImageSet mean;      // one layer per gate layer (empty for an adjoint render without renderImage)
  ImageSet variance;  // variance of each pixel's mean (its squared standard error)
  // Per derivative lane (RenderOptions::derivativeLanes): d mean / d θ and its variance.
  std::vector<ImageSet> derivatives;
  std::vector<ImageSet> derivativeVariances;
  RenderStats stats;
  RenderPlan plan;
  std::map<std::string, double> passMilliseconds;  // with RenderOptions::profile
};

class Renderer {
 public:
  explicit Renderer(VulkanContext& context);
  ~Renderer();
  // A render of `scene` as `setup` sees it.
  RenderResult render(DeviceScene& scene, const RenderSetup& setup, const RenderOptions& options);
  // One render of several views of `scene`: `setup` gives the gate, the settings (but the seed), the
  // camera type and the image size; every view, the same. Its images hold the views' images one
  // below the other (splitViews); its adjoint image, likewise.
  RenderResult render(DeviceScene& scene, const RenderSetup& setup, const std::vector<RenderView>& views,
                      const RenderOptions& options);
  // A render of a scene uploaded for this render alone.
  RenderResult render(const Scene& scene, const RenderOptions& options);
  VulkanContext& context() const;

 private:
  RenderResult renderViews(DeviceScene& scene, const RenderSetup& setup, const std::vector<RenderView>* views,
                           const RenderOptions& options);
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace vktg
