// Samples for each term of a loss gradient, chosen by a measured pilot. The gradient is a sum of
// independent estimates (interior, edges, and the path-length boundary's two: connections from path
// vertices and from the camera), so its variance is the sum of theirs, V_i / x_i for a term given
// x_i times the reference samples (the interior term's). Its time is Σ (f_i + P_i x_i): a fixed part
// per render (launches, submissions) and a part per sample. The variance of a gradient of given
// time is least when x_i ∝ sqrt(V_i / P_i) (a Lagrange multiplier on the time; the fixed parts are
// paid whatever x_i). The interior term keeps the samples the experiment gives it and the others
// follow from it: a term whose samples buy little variance (a heightfield's edges seen from above)
// gets few, a cheap and noisy one more.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "plan/terms.h"

namespace vktg {

// One round of a term's pilot: its loss gradient with random numbers of its own, at `spp` samples
// per pixel, and the seconds it took.
struct TermPilotRound {
  std::vector<double> gradient;  // d loss / d θ
  uint32_t spp = 0;
  double seconds = 0;
};

struct TermPilotRuns {
  // Interior, Edge, PathLength (the path-length boundary's connections from path vertices) or
  // PathLengthFromCamera (its connections from the camera, splatted)
  Term term = Term::Interior;
  std::vector<TermPilotRound> rounds;
};

struct TermCost {
  Term term = Term::Interior;
  double variance = 0;          // Σ_k Var(g_ik) / E[g_k²] at the reference samples (see allocateTermSamples)
  double fixedSeconds = 0;      // f_i: per gradient, whatever its samples
  double sampleSeconds = 0;     // P_i: the part that scales with the samples, at the reference samples
  double spp = 0;               // what the allocation gives the term (samples per pixel, on average)
};

struct TermAllocation {
  // Samples per pixel, fractional below 1 (roundTermSpp); 0: the term did not run in the pilot (keep
  // the experiment's).
  double sppEdge = 0, sppBoundary = 0, sppBoundaryCamera = 0;
  std::vector<TermCost> terms;
  // Predicted variance of a gradient at the allocation, relative to every term at the interior's
  // samples (the same weighting), and its predicted seconds relative to theirs.
  double varianceRatio = 1, secondsRatio = 1;
  std::vector<std::string> reasons;
};

// Pilot rounds per term, alternating between two sample counts (termPilotSpp): the rounds at each
// count give each parameter's variance 2 degrees of freedom, the two counts the time model. Summed
// over parameters and square-rooted before it sets a sample count, the variance need not be exact,
// but a term with rare large samples (a box gate's jumps) measured 3x too low from 3 degrees of
// freedom (`vktg bench optimize --sizes 11 --scale 0.5`: 0.22 against 0.77 from 14).
inline constexpr uint32_t kTermPilotRounds = 6;
// Samples per pixel of round `round` when the interior term has `spp`: even rounds at spp, odd ones
// at spp / 2 (at 2 when spp is 1).
uint32_t termPilotSpp(uint32_t round, uint32_t spp);
// Allocations stay within [kTermPilotMinSpp, kTermPilotMaxFactor × the interior's samples]: a term
// measured with little variance still gets a sample every few pixels (unbiased either way; its
// variance estimate, from a few rounds, may be low), and a noisy pilot cannot ask for a gradient
// many times the experiment's. Below one sample per pixel a term's passes take whole samples
// spread over the pixels (RenderOptions::samplesPerPixel), so the optimum is not rounded up to one:
// allocations round to whole samples per pixel from 1 up, to sixteenths below.
inline constexpr uint32_t kTermPilotMaxFactor = 8;
inline constexpr double kTermPilotMinSpp = 0.125;
inline constexpr double kTermPilotSppSteps = 16;
double roundTermSpp(double spp);
// The part of a term's time at the reference samples that the allocation takes to scale with them,
// at least: a launch-bound term (all fixed, within timing noise) would otherwise be given samples
// as if they were free.
inline constexpr double kTermPilotMinSampleShare = 0.1;
// An allocation for the path-length boundary's connections from path vertices (Term::PathLength) within
// this factor of the interior's samples is set equal to them: they then share the interior term's
// paths, which costs less than the two traced apart that the pilot timed. Its connections from the
// camera are splatted and share no paths.
inline constexpr double kTermPilotShareFactor = 1.5;

// The allocation from finished pilot runs (pure: no device). Each parameter k is weighted by
// 1 / E[g_k²], the second moment of its whole gradient (the sum of the terms' means squared plus
// their variances), so that parameters of different units count alike, as Adam's per-parameter
// scaling sees them. A term's variance comes from its pairs of rounds at equal samples, scaled to
// the reference; its time model from all its rounds (fitPilotTimes). Needs the interior term among
// `runs` with variance > 0; otherwise the allocation keeps the experiment's (every count 0) and says
// why.
TermAllocation allocateTermSamples(const std::vector<TermPilotRuns>& runs, uint32_t sppInterior);

}  // namespace vktg
