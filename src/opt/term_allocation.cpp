#include "opt/term_allocation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vktg/error.h"

namespace vktg {
namespace {

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace

TermAllocation allocateTermSamples(const std::vector<TermPilotRuns>& runs, uint32_t sppInterior) {
  TermAllocation a;
  const size_t parameters = runs.empty() || runs.front().gradients.empty() ? 0 : runs.front().gradients.front().size();
  // Per term and parameter: the mean and the unbiased variance over rounds.
  std::vector<std::vector<double>> means(runs.size(), std::vector<double>(parameters, 0.0)),
      variances(runs.size(), std::vector<double>(parameters, 0.0));
  for (size_t i = 0; i < runs.size(); ++i) {
    const auto& g = runs[i].gradients;
    if (g.size() < 2) throw Error("internal: a term's pilot needs two rounds at least");
    for (size_t k = 0; k < parameters; ++k) {
      double mean = 0, square = 0;
      for (const auto& round : g) mean += round.at(k);
      mean /= double(g.size());
      for (const auto& round : g) square += (round[k] - mean) * (round[k] - mean);
      means[i][k] = mean;
      variances[i][k] = square / double(g.size() - 1);
    }
  }
  for (size_t i = 0; i < runs.size(); ++i) a.terms.push_back({runs[i].term, 0.0, runs[i].seconds, 0});
  for (size_t k = 0; k < parameters; ++k) {
    double mean = 0, variance = 0;
    for (size_t i = 0; i < runs.size(); ++i) mean += means[i][k], variance += variances[i][k];
    const double moment = mean * mean + variance;
    if (!(moment > 0) || !std::isfinite(moment)) continue;  // a parameter no term moves
    for (size_t i = 0; i < runs.size(); ++i) a.terms[i].variance += variances[i][k] / moment;
  }
  auto interior = std::find_if(a.terms.begin(), a.terms.end(), [](const TermCost& t) { return t.term == "interior"; });
  if (interior == a.terms.end() || !(interior->variance > 0) || !(interior->seconds > 0)) {
    a.reasons.push_back(interior == a.terms.end()
                            ? "term samples: the experiment's (the interior term, which the others are set against, does not run)"
                            : "term samples: the experiment's (the interior term's pilot measured no variance)");
    return a;
  }
  const double reference = std::sqrt(interior->variance / interior->seconds);
  double variance = 0, allocatedVariance = 0, seconds = 0, allocatedSeconds = 0;
  for (TermCost& t : a.terms) {
    // Timing noise or a term that adds nothing: the fewest samples (still unbiased).
    const double ratio = t.seconds > 0 ? std::sqrt(t.variance / t.seconds) / reference : 0.0;
    double spp = t.term == "interior" ? double(sppInterior) : std::round(ratio * sppInterior);
    spp = std::clamp(spp, 1.0, double(kTermPilotMaxFactor) * sppInterior);
    if (t.term == "boundary" && ratio * kTermPilotShareFactor >= 1.0 && ratio <= kTermPilotShareFactor)
      spp = sppInterior;
    t.spp = uint32_t(spp);
    const double x = spp / sppInterior;
    variance += t.variance, allocatedVariance += t.variance / x;
    seconds += t.seconds, allocatedSeconds += t.seconds * x;
    if (t.term == "edges") a.sppEdge = t.spp;
    if (t.term == "boundary") a.sppBoundary = t.spp;
  }
  a.varianceRatio = variance > 0 ? allocatedVariance / variance : 1.0;
  a.secondsRatio = seconds > 0 ? allocatedSeconds / seconds : 1.0;
  a.reasons.push_back("term samples from a pilot of " + std::to_string(runs.front().gradients.size()) +
                      " gradients per term: samples ∝ sqrt(variance / seconds), the interior term's fixed");
  return a;
}

std::vector<std::string> describeAllocation(const TermAllocation& a) {
  std::vector<std::string> lines = a.reasons;
  for (const TermCost& t : a.terms)
    lines.push_back("  " + t.term + ": variance " + format("%.3g", t.variance) + ", " + format("%.3g s", t.seconds) +
                    " per pilot gradient -> " + std::to_string(t.spp) + " spp");
  if (!a.terms.empty() && (a.sppEdge || a.sppBoundary))
    lines.push_back("  predicted against every term at the interior's samples: variance " + format("%.2fx", a.varianceRatio) +
                    ", seconds " + format("%.2fx", a.secondsRatio));
  return lines;
}

}  // namespace vktg
