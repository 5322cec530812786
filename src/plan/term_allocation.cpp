#include "plan/term_allocation.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "plan/pilot_time_model.h"
#include "vktg/error.h"

namespace vktg {
namespace {

// Per parameter: the mean over all rounds, and the variance per sample per pixel, pooled over the
// groups of rounds at equal samples (each group's unbiased variance times its samples, weighted by
// its degrees of freedom).
void termStatistics(const TermPilotRuns& run, size_t parameters, std::vector<double>& mean, std::vector<double>& perSample) {
  std::map<uint32_t, std::vector<const TermPilotRound*>> groups;
  for (const TermPilotRound& r : run.rounds) {
    if (r.gradient.size() != parameters || r.spp == 0) throw Error("internal: term pilot rounds differ in their parameters");
    groups[r.spp].push_back(&r);
  }
  mean.assign(parameters, 0.0);
  perSample.assign(parameters, 0.0);
  double freedom = 0;
  for (const TermPilotRound& r : run.rounds)
    for (size_t k = 0; k < parameters; ++k) mean[k] += r.gradient[k] / double(run.rounds.size());
  for (const auto& [spp, rounds] : groups) {
    if (rounds.size() < 2) continue;
    for (size_t k = 0; k < parameters; ++k) {
      double m = 0, square = 0;
      for (const TermPilotRound* r : rounds) m += r->gradient[k] / double(rounds.size());
      for (const TermPilotRound* r : rounds) square += (r->gradient[k] - m) * (r->gradient[k] - m);
      perSample[k] += square * spp;  // (n - 1) × unbiased variance × spp
    }
    freedom += double(rounds.size() - 1);
  }
  if (freedom == 0) throw Error("internal: a term's pilot needs two rounds at equal samples");
  for (double& v : perSample) v /= freedom;
}

}  // namespace

double roundTermSpp(double spp) {
  return spp >= 1.0 ? std::round(spp) : std::round(spp * kTermPilotSppSteps) / kTermPilotSppSteps;
}

uint32_t termPilotSpp(uint32_t round, uint32_t spp) {
  if (round % 2 == 0) return spp;
  return spp > 1 ? spp / 2 : 2;
}

TermAllocation allocateTermSamples(const std::vector<TermPilotRuns>& runs, uint32_t sppInterior) {
  TermAllocation a;
  const size_t parameters = runs.empty() || runs.front().rounds.empty() ? 0 : runs.front().rounds.front().gradient.size();
  std::vector<std::vector<double>> means(runs.size()), variances(runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    termStatistics(runs[i], parameters, means[i], variances[i]);
    for (double& v : variances[i]) v /= sppInterior;  // at the reference samples
    std::vector<double> seconds, spp;
    for (const TermPilotRound& r : runs[i].rounds) seconds.push_back(r.seconds), spp.push_back(r.spp);
    const PilotTimeModel model = fitPilotTimes(seconds, spp);
    TermCost cost{runs[i].term, 0.0, model.fixed, model.perSpp * sppInterior, 0};
    const double total = cost.fixedSeconds + cost.sampleSeconds;
    cost.sampleSeconds = std::max(cost.sampleSeconds, kTermPilotMinSampleShare * total);
    cost.fixedSeconds = total - cost.sampleSeconds;
    a.terms.push_back(cost);
  }
  for (size_t k = 0; k < parameters; ++k) {
    double mean = 0, variance = 0;
    for (size_t i = 0; i < runs.size(); ++i) mean += means[i][k], variance += variances[i][k];
    const double moment = mean * mean + variance;
    if (!(moment > 0) || !std::isfinite(moment)) continue;  // a parameter no term moves
    for (size_t i = 0; i < runs.size(); ++i) a.terms[i].variance += variances[i][k] / moment;
  }
  auto interior = std::find_if(a.terms.begin(), a.terms.end(), [](const TermCost& t) { return t.term == Term::Interior; });
  if (interior == a.terms.end() || !(interior->variance > 0) || !(interior->sampleSeconds > 0)) {
    a.reasons.push_back(interior == a.terms.end()
                            ? "term samples: the experiment's (the interior term, which the others are set against, does not run)"
                            : "term samples: the experiment's (the interior term's pilot measured no variance)");
    return a;
  }
  const double reference = std::sqrt(interior->variance / interior->sampleSeconds);
  double variance = 0, allocatedVariance = 0, seconds = 0, allocatedSeconds = 0;
  for (TermCost& t : a.terms) {
    const double ratio = t.sampleSeconds > 0 ? std::sqrt(t.variance / t.sampleSeconds) / reference : 0.0;
    // A term that adds no measured variance gets the fewest samples (still unbiased).
    double spp = t.term == Term::Interior ? double(sppInterior) : roundTermSpp(ratio * sppInterior);
    spp = std::clamp(spp, kTermPilotMinSpp, double(kTermPilotMaxFactor) * sppInterior);
    if (t.term == Term::PathLength && ratio * kTermPilotShareFactor >= 1.0 && ratio <= kTermPilotShareFactor)
      spp = sppInterior;
    t.spp = spp;
    const double x = spp / sppInterior;
    variance += t.variance, allocatedVariance += t.variance / x;
    seconds += t.fixedSeconds + t.sampleSeconds, allocatedSeconds += t.fixedSeconds + t.sampleSeconds * x;
    if (t.term == Term::Edge) a.sppEdge = t.spp;
    if (t.term == Term::PathLength) a.sppBoundary = t.spp;
    if (t.term == Term::PathLengthFromCamera) a.sppBoundaryCamera = t.spp;
  }
  a.varianceRatio = variance > 0 ? allocatedVariance / variance : 1.0;
  a.secondsRatio = seconds > 0 ? allocatedSeconds / seconds : 1.0;
  a.reasons.push_back("term samples from a pilot of " + std::to_string(runs.front().rounds.size()) +
                      " gradients per term: samples ∝ sqrt(variance / seconds per sample), the interior term's fixed");
  return a;
}

}  // namespace vktg
