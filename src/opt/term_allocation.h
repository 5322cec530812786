// Samples for each term of a loss gradient, chosen by a measured pilot. The gradient is a sum of
// independent estimates (interior, edges, path-length boundary), so its variance is the sum of
// theirs, V_i / x_i for a term given x_i times the pilot's samples; with c_i the seconds of one
// pilot gradient of term i, the variance of a gradient of fixed cost is least when
// x_i ∝ sqrt(V_i / c_i) (a Lagrange multiplier on sum c_i x_i). The interior term keeps the samples
// the experiment gives it and the others follow from it. A term whose samples buy little variance
// (a heightfield's edges seen from above) thus gets few, one that is cheap and noisy more.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace vktg {

// One term's pilot: the loss gradients of a few rounds with independent random numbers, every
// round at the interior term's samples per pixel, and their wall-clock seconds.
struct TermPilotRuns {
  std::string term;                            // "interior", "edges", "boundary"
  std::vector<std::vector<double>> gradients;  // per round: d loss / d θ
  double seconds = 0;                          // of one round (the median)
};

struct TermCost {
  std::string term;
  double variance = 0;  // Σ_k Var(g_ik) / E[g_k²] at the pilot's samples (see allocateTermSamples)
  double seconds = 0;   // seconds of one pilot gradient
  uint32_t spp = 0;     // what the allocation gives the term
};

struct TermAllocation {
  uint32_t sppEdge = 0, sppBoundary = 0;  // 0: the term did not run in the pilot (keep the experiment's)
  std::vector<TermCost> terms;
  // Predicted variance of a gradient at the allocation, relative to every term at the interior's
  // samples (the same weighting), and its predicted seconds relative to theirs.
  double varianceRatio = 1, secondsRatio = 1;
  std::vector<std::string> reasons;
};

// Pilot rounds per term: the variance of each parameter's derivative from 3 degrees of freedom,
// summed over parameters (and square-rooted) before it sets a sample count.
inline constexpr uint32_t kTermPilotRounds = 4;
// Allocations stay within [1, kTermPilotMaxFactor × the interior's samples]: a term measured with
// little variance still gets a sample per pixel (unbiased either way), and a noisy pilot cannot ask
// for a gradient many times the experiment's.
inline constexpr uint32_t kTermPilotMaxFactor = 8;
// A path-length-boundary allocation within this factor of the interior's samples is set equal to
// them: the per-pixel part then shares the interior term's paths, which costs less than the two
// traced apart that the pilot timed.
inline constexpr double kTermPilotShareFactor = 1.5;

// The allocation from finished pilot runs (pure: no device). Each parameter k is weighted by
// 1 / E[g_k²], the second moment of its whole gradient (the sum of the terms' means squared plus
// their variances), so that parameters of different units count alike, as Adam's per-parameter
// scaling sees them. Needs the interior term among `runs` with variance > 0; otherwise the
// allocation keeps the experiment's (sppEdge = sppBoundary = 0) and says why.
TermAllocation allocateTermSamples(const std::vector<TermPilotRuns>& runs, uint32_t sppInterior);

// The allocation's lines for --explain and the progress output.
std::vector<std::string> describeAllocation(const TermAllocation& allocation);

}  // namespace vktg
