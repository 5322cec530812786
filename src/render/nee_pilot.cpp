#include "render/nee_pilot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "render/relative_error.h"

namespace vktg {
namespace {

// Each layer averaged over the (2r+1)^2 pixels around each pixel (those inside the image).
std::vector<float> boxBlurred(const std::vector<float>& pixels, uint32_t width, uint32_t height, int r) {
  std::vector<float> out(pixels.size());
  const size_t perLayer = size_t(width) * height;
  for (size_t layer = 0; layer * perLayer < pixels.size(); ++layer)
    for (int y = 0; y < int(height); ++y)
      for (int x = 0; x < int(width); ++x) {
        double total = 0;
        int count = 0;
        for (int j = std::max(0, y - r); j <= std::min(int(height) - 1, y + r); ++j)
          for (int i = std::max(0, x - r); i <= std::min(int(width) - 1, x + r); ++i, ++count)
            total += pixels[layer * perLayer + size_t(j) * width + i];
        out[layer * perLayer + size_t(y) * width + x] = float(total / count);
      }
  return out;
}

}  // namespace

uint32_t pilotSpp(uint32_t spp) { return spp < kPilotMinRenderSpp ? 0u : spp / kPilotFraction; }

PilotDecision decideFromPilot(const std::vector<PilotRun>& runs, uint32_t renderSpp) {
  PilotDecision decision;
  const size_t n = runs.size();
  std::vector<std::vector<float>> means(n), variances(n);
  std::vector<double> totals(n), totalVariances(n);
  size_t brightest = 0;
  for (size_t c = 0; c < n; ++c) {
    means[c] = runs[c].mean.allPixels();
    variances[c] = runs[c].variance.allPixels();
    totals[c] = std::accumulate(means[c].begin(), means[c].end(), 0.0);
    totalVariances[c] = std::accumulate(variances[c].begin(), variances[c].end(), 0.0);
    if (totals[c] > totals[brightest]) brightest = c;
  }
  decision.estimates.resize(n);
  for (size_t c = 0; c < n; ++c) {
    PilotEstimate& e = decision.estimates[c];
    e.nee = runs[c].nee;
    e.seconds = runs[c].fixedSeconds + renderSpp * runs[c].secondsPerSpp;
    e.lightShare = totals[brightest] > 0 ? totals[c] / totals[brightest] : 1.0;
    const double spread = std::sqrt(totalVariances[c] + totalVariances[brightest]);
    const double gap = totals[brightest] - totals[c];
    e.shortfall = gap > 0 ? (spread > 0 ? gap / spread : INFINITY) : 0.0;
    e.excluded = e.shortfall > kPilotShortfallLimit;
  }
  if (n == 0 || !(totals[brightest] > 0)) {
    decision.reasons.push_back("the pilot saw no light in the gate: the rule decides");
    return decision;
  }
  // One reference for every estimator (the mean of the trusted runs' images), so their relMSEs
  // share a denominator and differ only by their variances. Blurred: a pilot's pixel is noisy, and
  // a rare large sample would raise its own denominator along with its variance, hiding the very
  // noise the pilot must see (measured: the heavy-tailed estimator then looked 2x better than it is).
  std::vector<float> pooled(means[brightest].size(), 0.0f);
  size_t trusted = 0;
  for (size_t c = 0; c < n; ++c) {
    if (decision.estimates[c].excluded) continue;
    for (size_t i = 0; i < pooled.size(); ++i) pooled[i] += means[c][i];
    ++trusted;
  }
  for (float& r : pooled) r /= float(trusted);
  const std::vector<float> reference =
      boxBlurred(pooled, runs[brightest].mean.width, runs[brightest].mean.height, kPilotReferenceRadius);
  size_t best = n;
  for (size_t c = 0; c < n; ++c) {
    PilotEstimate& e = decision.estimates[c];
    // An unbiased estimator's variance falls as 1/n: from the pilot's samples to the render's.
    e.relMse = expectedRelMse(variances[c], reference) * runs[c].spp / renderSpp;
    e.efficiency = e.relMse * e.seconds;
    if (!e.excluded && (best == n || e.efficiency < decision.estimates[best].efficiency)) best = c;
  }
  const PilotEstimate& chosen = decision.estimates[best];
  decision.choice = chosen.nee;
  decision.reasons.push_back(formatReason(
      "%s NEE: the lowest predicted relMSE x time of the %u-spp render, from a pilot of %u spp per estimator on this device:",
      neeModeName(chosen.nee), renderSpp, runs[best].spp));
  for (size_t c = 0; c < n; ++c) {
    const PilotEstimate& e = decision.estimates[c];
    const std::string time = formatReason("%-11s %.3g s (%.3g s + %.3g ms per spp)", neeModeName(e.nee), e.seconds,
                                          runs[c].fixedSeconds, 1e3 * runs[c].secondsPerSpp);
    if (e.excluded)
      decision.reasons.push_back(formatReason(
          "  %s; its image holds %.3g of the light the others found (%.1f standard errors short): too few of its rare "
          "samples to measure its variance; excluded",
          time.c_str(), e.lightShare, e.shortfall));
    else
      decision.reasons.push_back(formatReason("  %s, relMSE %.3g, relMSE x time %.3g (%.3gx the chosen)", time.c_str(),
                                              e.relMse, e.efficiency,
                                              chosen.efficiency > 0 ? e.efficiency / chosen.efficiency : 1.0));
  }
  return decision;
}

bool pilotApplies(const RenderSetup& setup, const RenderOptions& options, std::string* note) {
  if (options.nee != NeeMode::Auto || setup.settings.nee != NeeMode::Auto) return false;  // requested
  if (setup.gate.type == GateType::Steady) return false;  // only standard NEE can render it
  // The pilot measures images, not derivatives.
  if (!options.derivativeLanes.empty() || options.adjoint || options.term != Term::Interior) return false;
  if (pilotSpp(setup.settings.spp) == 0) {
    if (note)
      *note = formatReason("no pilot: %u spp is too few to spend 1/%u of them on each estimator (needs %u)",
                           setup.settings.spp, kPilotFraction, kPilotMinRenderSpp);
    return false;
  }
  return true;
}

PilotDecision runNeePilot(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup, const RenderOptions& options,
                          bool onlyWhereItPays) {
  const NeeMode candidates[] = {NeeMode::Standard, NeeMode::Ellipsoidal, NeeMode::Mis};
  const uint32_t h = (pilotSpp(setup.settings.spp) - 2) / 3;
  const uint32_t sizes[] = {2, h, 2 * h};
  std::vector<RenderResult> rounds[3];
  for (auto& round : rounds) round.resize(3);
  // Renders round `round` of estimator k; returns its wall time (pipelines created on first use included).
  auto render = [&](uint32_t k, uint32_t round) {
    RenderSetup pilot = setup;
    pilot.settings.spp = sizes[round];
    // Seeds apart from the render's and from each other: the pilot is independent of the render.
    pilot.settings.seed = setup.settings.seed + 0x9E3779B9u * (3 * k + round + 1);
    RenderOptions o = options;
    o.nee = candidates[k];
    o.neeNotes.clear();
    o.progress = nullptr;
    const auto start = std::chrono::steady_clock::now();
    rounds[round][k] = renderer.render(scene, pilot, o);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // The rule's estimator first: its pilot alone predicts the render's time and what the whole pilot
  // would cost (its first render's wall time beyond the batches is the pipelines and buffers each
  // estimator sets up once), and the pilot stops there if it would cost more than kPilotMaxShare.
  // (Every estimator's first render is of 2 spp so that this set-up is paid on a small render.)
  const NeeMode ruled = planRender(setup, scene.prepared(), NeeMode::Auto).nee;
  const uint32_t first = ruled == NeeMode::Ellipsoidal ? 1u : 0u;
  const double setupSeconds = render(first, 0) - rounds[0][first].stats.seconds;
  render(first, 1);
  render(first, 2);
  // Whether the whole pilot pays, from the first estimator's time model.
  const std::vector<double> counts = {double(sizes[0]), double(sizes[1]), double(sizes[2])};
  auto timesOf = [&](uint32_t k) {
    return std::vector<double>{rounds[0][k].stats.seconds, rounds[1][k].stats.seconds, rounds[2][k].stats.seconds};
  };
  const PilotTimeModel firstModel = fitPilotTimes(timesOf(first), counts);
  const double renderSeconds = firstModel.fixed + setup.settings.spp * firstModel.perSpp;
  const double pilotSeconds = 3 * (setupSeconds + 3 * firstModel.fixed + (2 + 3 * h) * firstModel.perSpp);
  const bool pays = pilotSeconds <= kPilotMaxShare * renderSeconds;
  if (onlyWhereItPays && !pays) {
    PilotDecision stopped;
    stopped.pays = false;
    stopped.reasons.push_back(formatReason(
        "no pilot: with %s NEE the render would take %.3g s and a pilot of all three estimators %.3g s, more than "
        "%.0f%% of it (a pilot of %s NEE alone told)",
        neeModeName(ruled), renderSeconds, pilotSeconds, 100 * kPilotMaxShare, neeModeName(ruled)));
    return stopped;
  }
  // The others round by round, in turn, so that a drift in the machine's speed touches both alike.
  for (uint32_t round = 0; round < 3; ++round)
    for (uint32_t k = 0; k < 3; ++k)
      if (k != first) render(k, round);
  // Each estimator's time model (batch times exclude the pipelines the first round created).
  std::vector<PilotRun> runs;
  for (uint32_t k = 0; k < 3; ++k) {
    const PilotTimeModel model = fitPilotTimes(timesOf(k), counts);
    PilotRun run{candidates[k], 2 + 3 * h, model.fixed, model.perSpp, rounds[0][k].mean, rounds[0][k].variance};
    // The three renders' mean, weighted by their samples, and the variance of that mean.
    for (size_t l = 0; l < run.mean.layers.size(); ++l)
      for (size_t i = 0; i < run.mean.layers[l].pixels.size(); ++i) {
        double mean = 0, variance = 0;
        for (uint32_t round = 0; round < 3; ++round) {
          const double w = double(sizes[round]) / run.spp;
          mean += w * rounds[round][k].mean.layers[l].pixels[i];
          variance += w * w * rounds[round][k].variance.layers[l].pixels[i];
        }
        run.mean.layers[l].pixels[i] = float(mean);
        run.variance.layers[l].pixels[i] = float(variance);
      }
    runs.push_back(std::move(run));
  }
  PilotDecision decision = decideFromPilot(runs, setup.settings.spp);
  decision.pays = pays;
  return decision;
}

void chooseNeeByPilot(Renderer& renderer, DeviceScene& scene, const RenderSetup& setup, RenderOptions& options,
                      bool onlyWhereItPays) {
  std::string note;
  if (!pilotApplies(setup, options, &note)) {
    if (!note.empty()) options.neeNotes = {note};
    return;
  }
  PilotDecision decision = runNeePilot(renderer, scene, setup, options, onlyWhereItPays);
  options.neeNotes = decision.reasons;
  if (decision.choice) options.nee = *decision.choice;
}

}  // namespace vktg
