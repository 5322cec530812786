// The measured-cost choice of next-event estimation: a short pilot renders the image with each
// estimator (standard, ellipsoidal, MIS) at a few samples per pixel on this device and scene, and
// the render uses the one with the lowest predicted relMSE x time. For an unbiased estimator that
// product does not depend on the sample count, so a pilot at 1/32 of the render's samples predicts
// the render's. `--explain` prints the pilot's numbers.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "plan/pilot_time_model.h"

namespace vktg {

// One estimator's pilot: its renders' combined image with the variance of each pixel's mean (all
// layers of a transient stack), their samples per pixel, and its time model: a render of n spp
// takes fixedSeconds + n x secondsPerSpp (the fixed part is launch, dispatch and per-batch cost,
// which a small pilot would otherwise mistake for the estimator's).
struct PilotRun {
  NeeMode nee = NeeMode::Standard;
  uint32_t spp = 0;
  double fixedSeconds = 0, secondsPerSpp = 0;
  ImageSet mean, variance;
};

// What the pilot predicts for the render of `renderSpp` samples with one estimator.
struct PilotEstimate {
  NeeMode nee = NeeMode::Standard;
  double seconds = 0;     // predicted time of the render
  double relMse = 0;      // predicted relMSE of the render, against the pooled (blurred) pilot image
  double efficiency = 0;  // relMse x seconds (lower is better)
  double lightShare = 1;  // this pilot image's total / the largest one's
  double shortfall = 0;   // that difference in standard errors of the two totals
  bool excluded = false;  // its image falls short: it missed rare samples, its variance is unreliable
};

struct PilotDecision {
  std::vector<PilotEstimate> estimates;
  std::optional<NeeMode> choice;  // empty: the pilot could not tell (no light in the gate) or stopped
  std::vector<std::string> reasons;
  bool pays = true;  // the whole pilot was predicted to take at most kPilotMaxShare of the render
};

// Pilot samples per pixel for each estimator of a render of `spp` samples: 1/kPilotFraction of them,
// in three renders of 2, h and 2h spp (the first absorbs one-time costs, the other two give the time
// model; a pixel's variance needs 2 samples per render); 0 when the render is too small to pay for it.
inline constexpr uint32_t kPilotFraction = 32;
inline constexpr uint32_t kPilotMinRenderSpp = 256;
uint32_t pilotSpp(uint32_t spp);

// A run whose image total lies this many standard errors below another's is excluded: all three
// estimators are unbiased and every sample is non-negative, so a total that far short means the run
// saw too few of its rare large samples for its variance to be measured.
inline constexpr double kPilotShortfallLimit = 4.0;

// The pilot's relMSE divides by its pooled image, box-blurred over (2r+1)^2 pixels.
inline constexpr int kPilotReferenceRadius = 2;

// The decision for a render of `renderSpp` samples from finished pilot runs (pure: no device).
PilotDecision decideFromPilot(const std::vector<PilotRun>& runs, uint32_t renderSpp);

// Whether the pilot applies: NEE left to the planner (options and scene), a gate of finite extent,
// an image render (no derivatives), enough samples. `note` gets a line for the plan when only the
// sample count stood in the way (the other reasons are already in the plan's own lines).
bool pilotApplies(const RenderSetup& setup, const RenderOptions& options, std::string* note = nullptr);

// The most of a render's predicted time a pilot may take when it runs only where it pays.
inline constexpr double kPilotMaxShare = 0.25;

// Runs the pilot (independent random numbers: seeds apart from the render's) and decides. The
// estimator the gate-width rule would pick goes first; with `onlyWhereItPays`, the pilot stops
// after it (no choice, a reason saying why) when the whole pilot is predicted to take more than
// kPilotMaxShare of the render.
PilotDecision runNeePilot(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup, const RenderOptions& options,
                          bool onlyWhereItPays = true);

// Sets options.nee (and the reason the plan prints) from the pilot where it applies; otherwise
// records in the reason why the rule decides.
void chooseNeeByPilot(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup, RenderOptions& options,
                      bool onlyWhereItPays = true);

}  // namespace vktg
