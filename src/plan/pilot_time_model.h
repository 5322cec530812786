// Time models of pilot runs (the NEE pilot, the term pilot): t = fixed + n x perSpp.
#pragma once
#include <vector>

namespace vktg {

// An estimator's (or a gradient term's) time model, t = fixed + n x perSpp, fitted by least squares
// to its renders' batch times `seconds` at `spp` samples per pixel. Each estimator has its own fixed
// part: on a GPU a small render is launch-bound and an estimator's extra passes and buffers cost
// time per render, not per sample. (One fixed part shared by all three, fitted on an H200 to 32 x 32 pilots
// of the Cornell room, gave standard NEE 7.2 ms + 0 per spp and ellipsoidal 7.2 ms + 0.082 ms per
// spp: 24x standard's time at 2048 spp, where `bench nee` measures 1.3x per path.) Neither part is
// negative: a negative slope is timing noise of a launch-bound render (all fixed), a negative
// intercept the same the other way.
struct PilotTimeModel {
  double fixed = 0, perSpp = 0;
};
PilotTimeModel fitPilotTimes(const std::vector<double>& seconds, const std::vector<double>& spp);

}  // namespace vktg
