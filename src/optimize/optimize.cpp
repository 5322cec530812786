#include "optimize/optimize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <numeric>
#include <optional>

#include "render/frame_uniforms.h"
#include "grad/gradient.h"
#include "render/interrupt.h"
#include "render/memory_preflight.h"
#include "render/renderer.h"
#include "grad/term_pilot.h"
#include "opt/experiment.h"
#include "opt/loss.h"
#include "opt/optimizer.h"
#include "opt/regularizer.h"
#include "opt/run_directory.h"
#include "scene/contacts.h"
#include "opt/run_files.h"
#include "opt/target_figures.h"
#include "scene/seeds.h"
#include "vktg/error.h"
#include "vktg/parameter_model.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// Why a run that no other rule stopped ended (printed as "stopped after N iterations (...)").
constexpr const char* kReachedIterations = "it reached stop.iterations";

// Random numbers of iteration `iteration`, target `target` and use `use` (0: the render the loss
// comes from, 1: the gradient's renders; independent, as THEORY.md §7 requires; 2 + round: the
// term pilot's gradients; pass × kChainedPassUse: the chained interior passes after the first,
// above the target's bits): a hash of (seed, iteration, target, use).
constexpr uint32_t kChainedPassUse = 1u << 24;

uint32_t seedFor(uint32_t seed, uint64_t iteration, size_t target, uint32_t use) {
  return derivedSeed((uint64_t(seed) << 32) ^ (iteration * 0x9E3779B97F4A7C15ull) ^ (uint64_t(target) << 8) ^ use);
}

std::string formatSeconds(double s) {
  char text[32];
  if (s < 90) std::snprintf(text, sizeof text, "%.0fs", s);
  else if (s < 5400) std::snprintf(text, sizeof text, "%.0fm%02.0fs", std::floor(s / 60), std::fmod(s, 60));
  else std::snprintf(text, sizeof text, "%.0fh%02.0fm", std::floor(s / 3600), std::fmod(s / 60, 60));
  return text;
}

// How target t is seen: its camera and gate, the scene's render settings, its lights.
struct TargetSetup {
  RenderSetup setup;
  std::vector<std::pair<uint32_t, glm::vec3>> lights;
};

TargetSetup targetSetup(const Experiment& e, size_t t) {
  const Target& target = e.targets[t];
  TargetSetup s;
  Scene seen = sceneForTarget(e.scene, target);
  s.setup = RenderSetup::of(seen);
  s.setup.gate = target.gate;
  s.setup.pathOffset = target.view.pathOffset;
  s.lights = target.view.lightPositions;
  return s;
}

// The image of every view at the current θ (AdjointView without its adjoint), the views that one
// render can hold rendered together (viewGroups); `plans` receives each view's render plan.
std::vector<ImageSet> renderViewImages(Renderer& renderer, DeviceScene& scene, const std::vector<AdjointView>& views,
                                       const RenderOptions& options, std::vector<RenderPlan>& plans) {
  std::vector<ImageSet> images(views.size());
  plans.assign(views.size(), {});
  for (const std::vector<size_t>& group : viewGroups(views, true)) {
    const RenderResult r = renderGroup(renderer, scene, views, group, views[group.front()].setup, options);
    const std::vector<ImageSet> split = splitViews(r.mean, group.size());
    for (size_t k = 0; k < group.size(); ++k) {
      images[group[k]] = split[k];
      plans[group[k]] = r.plan;
    }
  }
  return images;
}

// The gate as θ sees it is shifted by the optimised gate-centre parameters.
double gateShift(const Experiment& e, const std::vector<double>& theta) {
  double shift = 0;
  for (size_t k = 0; k < e.parameters.size(); ++k)
    if (e.scene.parameters[e.parameters[k].sceneIndex].kind == ParameterKind::GateCenter) shift += theta[k];
  return shift;
}

std::vector<uint32_t> selectedIndices(const Experiment& e) {
  std::vector<uint32_t> out;
  for (const ExperimentParameter& p : e.parameters) out.push_back(p.sceneIndex);
  return out;
}

GradientOptions gradientOptions(const Experiment& e, uint64_t memoryBudget) {
  GradientOptions o;
  o.interior = e.budget.interior;
  o.edges = e.budget.edge;
  o.pathLength = e.budget.pathLength;
  o.sppEdge = e.budget.sppEdge;
  o.sppBoundary = e.budget.sppBoundary;
  o.sppBoundaryCamera = e.budget.sppBoundaryCamera;
  o.antithetic = e.budget.antithetic == "on" ? AntitheticMode::On : e.budget.antithetic == "off" ? AntitheticMode::Off
                                                                                                  : AntitheticMode::Auto;
  o.render.nee = e.budget.nee;
  o.render.memoryBudget = memoryBudget;
  return o;
}

std::vector<std::string> logColumns(const Experiment& e) {
  std::vector<std::string> columns = {"iteration", "loss"};
  for (const TargetEntry& entry : targetEntries(e)) columns.push_back("loss_" + entry.name);  // a scan's: its points' sum
  if (!e.regularizers.empty()) columns.push_back("regularization");
  columns.push_back("gradient_norm");
  if (parameterError(e.parameters, std::vector<double>(e.parameters.size(), 0.0))) columns.push_back("parameter_error");
  columns.push_back("seconds");
  return columns;
}

// Synthesised targets: rendered at the truth with independent random numbers, and kept in
// targets/ so that a resumed run reads them back instead of rendering again.
void synthesizeTargets(VulkanContext& context, Renderer& renderer, const Experiment& e, const ParameterModel& model,
                       const fs::path& run, uint64_t memoryBudget,
                       const std::function<void(const std::string&)>& progress, Collective* collective,
                       std::vector<ImageSet>& images) {
  std::vector<double> truth;
  for (const ExperimentParameter& p : e.parameters) truth.push_back(p.truth.value_or(0.0));
  // Targets rendered in an earlier run of this directory are read back; the others are rendered at
  // the truth, those that one render can hold together (viewGroups).
  std::vector<size_t> missing;
  std::vector<AdjointView> views;
  for (size_t t = 0; t < e.targets.size(); ++t) {
    const Target& target = e.targets[t];
    if (!target.synthesize) continue;
    const fs::path saved = run / "targets" / (target.name + ".exr");
    if (fs::exists(saved)) {
      images[t] = readExr(saved);
      continue;
    }
    TargetSetup s = targetSetup(e, t);
    s.setup.gate = s.setup.gate.shifted(gateShift(e, truth));
    s.setup.settings.spp = target.synthesizeSpp;
    s.setup.settings.seed = target.synthesizeSeed;
    missing.push_back(t);
    views.push_back({s.setup, s.lights, nullptr});
  }
  if (missing.empty()) return;
  if (progress) {
    std::string names;
    for (size_t k = 0; k < missing.size() && k < 4; ++k) names += (k ? ", " : "") + e.targets[missing[k]].name;
    if (missing.size() > 4) names += ", ...";
    progress("synthesising " + std::to_string(missing.size()) + " target" + (missing.size() > 1 ? "s" : "") +
             " at the truth: " + names);
  }
  // Spread over processes, each renders its share and all get every image (each the bits of its
  // own whichever views it is rendered with); rank 0 writes them.
  const Share share = shareOf(views.size(), collective);
  std::vector<ImageSet> rendered;
  std::string failure;
  try {
    if (!share.empty()) {
      DeviceScene truthScene(context, model, truth, truth);
      RenderOptions options;
      options.memoryBudget = memoryBudget;
      std::vector<RenderPlan> plans;
      const std::vector<AdjointView> mine(views.begin() + ptrdiff_t(share.begin), views.begin() + ptrdiff_t(share.end));
      rendered = renderViewImages(renderer, truthScene, mine, options, plans);
    }
  } catch (const Error& error) {
    if (!collective) throw;
    failure = error.what();
  }
  if (collective) {
    collective->agree(failure);
    rendered = allGatherImages(*collective, rendered);
  }
  for (size_t k = 0; k < missing.size(); ++k) {
    const size_t t = missing[k];
    images[t] = std::move(rendered[k]);
    checkTargetImageFinite(e, t, images[t]);
    if (!collective || collective->root()) writeExr(run / "targets" / (e.targets[t].name + ".exr"), images[t]);
  }
}

// d loss / d θ by central differences, one parameter at a time (2K evaluations of `loss`).
std::vector<double> centralDifferences(const std::function<double(const std::vector<double>&)>& loss,
                                       std::vector<double> theta, double step) {
  std::vector<double> d(theta.size());
  for (size_t k = 0; k < theta.size(); ++k) {
    const double value = theta[k];
    theta[k] = value + step;
    const double above = loss(theta);
    theta[k] = value - step;
    const double below = loss(theta);
    theta[k] = value;
    d[k] = (above - below) / (2 * step);
  }
  return d;
}

}  // namespace

struct Optimization::Impl {
  Impl(VulkanContext& context, const OptimizeOptions& options);

  VulkanContext& context;
  OptimizeOptions options;
  Collective* collective;              // null: one process
  bool root;                           // the process that writes the run directory
  fs::path run;
  Experiment e;
  RunInfo info;
  std::vector<TargetEntry> entries;
  std::vector<ImageSet> targets;       // per target
  std::vector<TargetSetup> setups;     // per target
  std::optional<ParameterModel> model;
  std::optional<Renderer> renderer;
  std::vector<double> theta;
  std::optional<Optimizer> optimizer;
  AdjointState adjoint;
  uint64_t iteration = 0;              // completed
  double secondsBefore = 0;            // of the runs this one resumes
  std::vector<double> initialLoss;     // per target, of the first iteration
  std::optional<DeviceScene> scene;
  std::optional<RunLog> log;
  GradientOptions gradient;
  bool termPilot = false;
  RenderOptions primalOptions;
  std::chrono::steady_clock::time_point runStart;
  std::vector<ImageSet> initialImages; // per target: the first iteration's, for the figures
  bool explained = false;
  std::string stopReason;
  std::optional<double> lastError;
  double lastLoss = 0;

  double elapsed() const {
    return secondsBefore + std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart).count();
  }
  // The first iteration's images, one file per "targets" entry (a scan's laid out as `vktg render
  // --scan` writes it), read back by a resumed run for its figures.
  fs::path initialImagePath(const TargetEntry& entry) const { return run / "images" / (entry.name + "_initial.exr"); }
  // The term pilot's choice (run.json keeps it): applied where the experiment asked for "auto".
  void applyPilot() {
    if (e.budget.sppEdgeAuto && info.pilotSppEdge > 0) gradient.sppEdge = info.pilotSppEdge;
    if (e.budget.sppBoundaryAuto && info.pilotSppBoundary > 0) gradient.sppBoundary = info.pilotSppBoundary;
    if (e.budget.sppBoundaryCameraAuto && info.pilotSppBoundaryCamera > 0) gradient.sppBoundaryCamera = info.pilotSppBoundaryCamera;
  }
  // The interruption check between iterations: spread over processes, all stop where any was asked to.
  void stopIfInterrupted() const {
    if (!collective) return throwIfInterrupted();
    if (const int signal = collective->agreeOnInterrupt(interruptSignal())) throw Interrupted(signal);
  }
  // Runs `part` on every process and compares how it went: spread over processes, a failure in any
  // is an Error in all (Collective::agree), so none waits for one that gave up.
  template <class Part>
  void together(Part&& part) {
    if (!collective) return part();
    std::string failure;
    try {
      part();
    } catch (const Error& error) {
      failure = error.what();
    }
    collective->agree(failure);
  }
  void writeState(uint64_t completed, double seconds) const {
    Checkpoint c;
    c.iteration = completed;
    for (const ExperimentParameter& p : e.parameters) c.names.push_back(p.name);
    c.theta = theta;
    c.optimizer = optimizer->state();
    c.bvhTheta.assign(scene->buildTheta().begin(), scene->buildTheta().end());
    c.adjointScale = adjoint.scale;
    c.seconds = seconds;
    c.initialLoss = initialLoss;
    writeCheckpoint(run / "checkpoint.bin", c);
  }
  void writeFigures() const { writeRunFigures(run, e, readLogColumns(run / "log.csv"), theta); }
  void say(const std::string& line) const {
    if (options.progress) options.progress(line);
  }
};

Optimization::Impl::Impl(VulkanContext& c, const OptimizeOptions& o)
    : context(c), options(o), collective(o.collective), root(!o.collective || o.collective->root()), run(o.runDirectory) {
  if (run.empty()) throw Error("--out: a run directory is required");
  // Everything that can be wrong with the input is checked before the run directory is touched.
  Checkpoint checkpoint;
  together([&] {
    if (options.resume) {
      checkResumableRun(run);
      info = readRunInfo(run);
      std::ifstream copy(run / "experiment.json", std::ios::binary);
      std::string text((std::istreambuf_iterator<char>(copy)), std::istreambuf_iterator<char>());
      e = parseExperimentJson(text, (run / "experiment.json").string(), info.experiment.parent_path(), info.defines);
      checkpoint = readCheckpoint(run / "checkpoint.bin");
      checkCheckpointMatches(run / "checkpoint.bin", checkpoint, e);
    } else {
      e = loadExperiment(options.experiment, options.defines);
      info = {options.experiment, options.memoryBudget, options.defines};
    }
    if (options.iterations) e.stop.iterations = *options.iterations;
    // Target images from files are read (and checked against their view and gate) here, once: a
    // scan's file once for all its points.
    entries = targetEntries(e);
    targets.resize(e.targets.size());
    for (const TargetEntry& entry : entries) {
      const Target& first = e.targets[entry.targets.front()];
      if (first.synthesize) {
        for (const ExperimentParameter& p : e.parameters)
          if (!p.truth) fail(e.source.string(), "targets[" + std::to_string(first.entry) + "].image", "synthesising needs a truth for every parameter; \"" + p.name + "\" has none");
        continue;
      }
      std::vector<ImageSet> images = loadTargetImages(e, entry);
      for (size_t k = 0; k < images.size(); ++k) targets[entry.targets[k]] = std::move(images[k]);
    }
    for (size_t t = 0; t < e.targets.size(); ++t) {
      // render.max_depth limits the model being fitted; the synthesised targets stand for the
      // measurement and keep the scene's depth (synthesizeTargets).
      setups.push_back(targetSetup(e, t));
      if (e.budget.maxDepth > 0) setups.back().setup.settings.maxDepth = e.budget.maxDepth;
    }
    // A target whose image and smallest batch alone exceed the device or --mem fails here, with what
    // it would need, before the run directory is touched (the scene comes on top).
    for (size_t t = 0; t < e.targets.size(); ++t) {
      const glm::uvec2 pixels = imagePixels(setups[t].setup.camera);
      try {
        checkRenderMemory(context, filmAndBatchNeed(pixels.x, pixels.y, setups[t].setup.gate.layers(), 1, 0),
                          info.memoryBudget);
      } catch (const Error& tooLarge) {
        fail(e.source.string(), "targets[" + std::to_string(e.targets[t].entry) + "]", tooLarge.what());
      }
    }
  });
  // Rank 0 prepares the run directory; the others read nothing of it until it is done.
  together([&] {
    if (!options.resume && root) {
      prepareRunDirectory(run, options.force);
      writeFileAtomic(run / "experiment.json", e.text);
      writeRunInfo(run, info);
      // A run interrupted before its first iteration ends (while synthesising targets, say) resumes
      // from here.
      Checkpoint start;
      for (const ExperimentParameter& p : e.parameters) {
        start.names.push_back(p.name);
        start.theta.push_back(p.initial);
      }
      start.optimizer = Optimizer(e.optimizer, e.parameters).state();
      start.bvhTheta = start.theta;
      writeCheckpoint(run / "checkpoint.bin", start);
    }
  });

  model.emplace(e.scene, selectedIndices(e));
  renderer.emplace(context);
  synthesizeTargets(context, *renderer, e, *model, run, info.memoryBudget, options.progress, collective, targets);
  for (size_t t = 0; t < e.targets.size(); ++t) {
    if (!e.targets[t].synthesize) continue;
    // A synthesised target read back on --resume is a file like any other: check it.
    const glm::uvec2 pixels = imagePixels(setups[t].setup.camera);
    checkTargetImageSize(e, t, targets[t], pixels.x, pixels.y, setups[t].setup.gate.layers());
    checkTargetImageFinite(e, t, targets[t]);
  }

  for (const ExperimentParameter& p : e.parameters) theta.push_back(p.initial);
  std::vector<double> bvhTheta = theta;
  optimizer.emplace(e.optimizer, e.parameters);
  if (options.resume) {
    theta = checkpoint.theta;
    bvhTheta = checkpoint.bvhTheta.empty() ? theta : checkpoint.bvhTheta;
    optimizer->restore(checkpoint.optimizer);
    adjoint.scale = checkpoint.adjointScale;
    iteration = checkpoint.iteration;
    secondsBefore = checkpoint.seconds;
    initialLoss = checkpoint.initialLoss;
  }
  scene.emplace(context, *model, theta, bvhTheta);
  // A run stopped before its first row may have no log yet; later ones must have theirs.
  const bool continueLog = options.resume && (iteration > 0 || fs::exists(run / "log.csv"));
  if (root) log.emplace(run / "log.csv", logColumns(e), continueLog, iteration);
  gradient = gradientOptions(e, info.memoryBudget);
  gradient.collective = collective;
  termPilot =
      (e.budget.sppEdgeAuto || e.budget.sppBoundaryAuto || e.budget.sppBoundaryCameraAuto) && !e.budget.finiteDifferences;
  if (termPilot && info.pilotDone) applyPilot();
  primalOptions.nee = e.budget.nee;
  primalOptions.memoryBudget = info.memoryBudget;
  runStart = std::chrono::steady_clock::now();
  initialImages.resize(e.targets.size());
  for (const TargetEntry& entry : entries) {
    const fs::path saved = initialImagePath(entry);
    if (!root || !fs::exists(saved)) continue;  // (figures are rank 0's)
    const ImageSet whole = readExr(saved);
    if (!entry.scan) {
      initialImages[entry.targets.front()] = whole;
      continue;
    }
    const std::vector<ImageSet> points = splitScanImage(e, entry, whole, saved.string());
    for (size_t k = 0; k < points.size(); ++k) initialImages[entry.targets[k]] = points[k];
  }
}

Optimization::Optimization(VulkanContext& context, const OptimizeOptions& options)
    : m_impl(std::make_unique<Impl>(context, options)) {}
Optimization::~Optimization() = default;

uint64_t Optimization::iteration() const { return m_impl->iteration; }
const std::vector<double>& Optimization::theta() const { return m_impl->theta; }
std::vector<std::string> Optimization::parameterNames() const {
  std::vector<std::string> names;
  for (const ExperimentParameter& p : m_impl->e.parameters) names.push_back(p.name);
  return names;
}
bool Optimization::stopped() const { return !m_impl->stopReason.empty() || m_impl->iteration >= m_impl->e.stop.iterations; }
const std::string& Optimization::stopReason() const { return m_impl->stopReason; }

Evaluation Optimization::evaluate() {
  Impl& m = *m_impl;
  const Experiment& e = m.e;
  DeviceScene& scene = *m.scene;
  Renderer& renderer = *m.renderer;
  const uint64_t i = m.iteration;
  m.stopIfInterrupted();
  const auto start = std::chrono::steady_clock::now();
  double pilotSeconds = 0;
  // This process's targets (all of them for one process): it renders those, and the losses,
  // gradient and images come together below.
  const Share mine = shareOf(e.targets.size(), m.collective);
  Evaluation out;
  out.iteration = i;
  out.theta = m.theta;
  // The BVH check goes by iteration, so a resumed run checks where the original did.
  scene.update(m.theta, m.model->movesVertices() && i % kBvhQualityCheckInterval == 0);
  const double shift = gateShift(e, m.theta);
  // The loss and its adjoint images, from renders with their own random numbers.
  // Indices into the vectors below are k = t - mine.begin.
  std::vector<double> losses(mine.size(), 0.0);
  std::vector<ImageSet> adjointImages(mine.size());
  std::vector<AdjointView> views, primalViews;
  for (size_t t = mine.begin; t < mine.end; ++t) {
    RenderSetup setup = m.setups[t].setup;
    setup.gate = setup.gate.shifted(shift);
    setup.settings.spp = e.budget.sppPrimal;
    setup.settings.seed = seedFor(e.seed, i, t, 0);
    primalViews.push_back({setup, m.setups[t].lights, nullptr});
  }
  std::vector<RenderPlan> plans;
  std::vector<ImageSet> primals = renderViewImages(renderer, scene, primalViews, m.primalOptions, plans);
  for (size_t k = 0; k < mine.size(); ++k) {
    const size_t t = mine.begin + k;
    if (m.options.explain && !m.explained)
      m.say("render plan (target " + e.targets[t].name + "):\n" + explainPlan(plans[k]));
    losses[k] = imageLoss(e.loss, primals[k], m.targets[t], e.targets[t].weight, &adjointImages[k]);
    RenderSetup setup = primalViews[k].setup;
    setup.settings.spp = e.budget.sppInterior;
    setup.settings.seed = seedFor(e.seed, i, t, 1);
    views.push_back({setup, m.setups[t].lights, nullptr});
  }
  for (size_t t = 0; t < views.size(); ++t) views[t].adjoint = &adjointImages[t];
  // Chained interior passes: pass 0 draws the unchained interior pass's random numbers (use 1),
  // the others uses of their own beyond the pilot's.
  std::optional<AdjointChain> chain;
  if (e.budget.interiorPasses > 1 && !e.budget.finiteDifferences) {
    chain.emplace();
    chain->passes = e.budget.interiorPasses;
    chain->images = primals;
    chain->imageSpp = e.budget.sppPrimal;
    chain->adjointOf = [&](size_t k, const ImageSet& image) {
      const size_t t = mine.begin + k;
      ImageSet adjoint;
      imageLoss(e.loss, image, m.targets[t], e.targets[t].weight, &adjoint);
      return adjoint;
    };
    chain->seedOf = [&](size_t k, uint32_t pass) {
      return seedFor(e.seed, i, mine.begin + k, pass == 0 ? 1 : pass * kChainedPassUse);
    };
  }
  LossGradient& g = out.gradient;
  if (e.budget.finiteDifferences) {
    // The loss at θ' rendered with the gradient's random numbers (use 1): both sides of a central
    // difference share them, so that their noise cancels as far as it can (common random numbers).
    auto lossAt = [&](const std::vector<double>& at) {
      m.stopIfInterrupted();
      scene.update(at, false);
      std::vector<double> targetLosses;
      for (size_t k = 0; k < mine.size(); ++k) {
        const size_t t = mine.begin + k;
        RenderSetup setup = views[k].setup;
        setup.gate = m.setups[t].setup.gate.shifted(gateShift(e, at));
        scene.placePointLights(m.setups[t].lights);
        targetLosses.push_back(imageLoss(e.loss, renderer.render(scene, setup, m.primalOptions).mean, m.targets[t], e.targets[t].weight));
      }
      // Summed in target order, whichever process rendered which.
      if (m.collective) targetLosses = allGatherDoubles(*m.collective, targetLosses);
      double total = 0;
      for (double l : targetLosses) total += l;
      return total;
    };
    g.theta = centralDifferences(lossAt, m.theta, e.budget.finiteDifferenceStep);
    scene.update(m.theta, false);
    g.plan.reasons.push_back("finite differences: the loss rendered at θ ± " +
                             std::to_string(e.budget.finiteDifferenceStep) + " for each of the " +
                             std::to_string(m.theta.size()) + " parameters (" +
                             std::to_string(2 * m.theta.size() * e.targets.size()) +
                             " renders at spp_interior), both sides with the same random numbers");
    g.stats.nonFinite = uint64_t(std::count_if(g.theta.begin(), g.theta.end(), [](double v) { return !std::isfinite(v); }));
  } else {
    if (m.termPilot && !m.info.pilotDone) {
      // At the first iteration's θ and adjoint images, with random numbers of its own (uses 2 +
      // round) and its own accumulators, so that the optimisation's gradients are those of a run
      // given the chosen samples from the start (a resumed run reads them from run.json).
      m.say("term pilot: " + std::to_string(kTermPilotRounds + 1) + " gradients of each term");
      const auto pilotStart = std::chrono::steady_clock::now();
      AdjointState pilotState;
      // The pilot's choice rests on timings: spread over processes, rank 0 pilots on its own
      // targets (a gradient of its own, not summed with the others') and its choice holds for all.
      TermAllocation allocation;
      if (m.root) {
        GradientOptions alone = m.gradient;
        alone.collective = nullptr;
        allocation = runTermPilot(renderer, scene, views, alone, pilotState,
                                  [&](uint32_t round, size_t k) { return seedFor(e.seed, i, mine.begin + k, 2 + round); });
      }
      if (m.collective) {
        allocation.sppEdge = broadcastDouble(*m.collective, allocation.sppEdge);
        allocation.sppBoundary = broadcastDouble(*m.collective, allocation.sppBoundary);
        allocation.sppBoundaryCamera = broadcastDouble(*m.collective, allocation.sppBoundaryCamera);
      }
      m.info.pilotSppEdge = allocation.sppEdge;
      m.info.pilotSppBoundary = allocation.sppBoundary;
      m.info.pilotSppBoundaryCamera = allocation.sppBoundaryCamera;
      m.info.pilotDone = true;
      if (m.root) writeRunInfo(m.run, m.info);
      m.applyPilot();
      // The iteration's time (log, ETA) is its own: the pilot runs once.
      pilotSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pilotStart).count();
      if (m.options.progress) {
        for (const std::string& line : describeAllocation(allocation)) m.say(line);
        m.say("term pilot: " + formatSeconds(pilotSeconds));
      }
    }
    const double scaleBefore = m.adjoint.scale;
    g = lossGradient(renderer, scene, views, m.gradient, m.adjoint, chain ? &*chain : nullptr);
    out.adjointScale = m.adjoint.scale;
    m.adjoint.scale = scaleBefore;
  }
  // The images of this θ: with a chain, from the render's samples and every interior pass's,
  // and the loss read from them.
  out.images = chain ? std::move(g.images) : std::move(primals);
  if (chain)
    for (size_t k = 0; k < mine.size(); ++k)
      losses[k] = imageLoss(e.loss, out.images[k], m.targets[mine.begin + k], e.targets[mine.begin + k].weight);
  // Spread over processes: every process gets every target's loss, rank 0 every image.
  out.targetLosses = m.collective ? allGatherDoubles(*m.collective, losses) : std::move(losses);
  // The images go to rank 0 only for the iterations whose figures step writes: a scan's are as
  // large as its capture, and would otherwise cross the network every iteration.
  if (m.collective) {
    const bool figures = i == 0 || i % e.imagesEvery == 0 || i + 1 == e.stop.iterations;
    out.images = figures ? gatherImages(*m.collective, out.images) : std::vector<ImageSet>{};
  }
  out.loss = 0;
  for (double l : out.targetLosses) out.loss += l;
  if (m.options.explain && !m.explained) {
    std::string plan = "gradient plan:\n";
    for (const std::string& r : g.plan.reasons) plan += "  - " + r + "\n";
    if (g.plan.edges)
      for (const std::string& r : describeContacts(scene.scene(), findContacts(scene.prepared(), scene.model()->movingShapes(),
                                                                                surfaceOffset(scene.prepared()))))
        plan += "  - " + r + "\n";
    if (chain)
      plan += "  - the adjoint image comes from a render with its own random numbers (seed of use 0); each chained interior\n"
              "    pass is weighted by the adjoint of that render and the passes before it, never by its own paths (a\n"
              "    correlated image would bias the gradient of any loss not linear in the image); the other terms by all of them\n";
    else if (!e.budget.finiteDifferences)
      plan += "  - the adjoint image comes from a render with its own random numbers (seed of use 0), independent of the\n"
              "    gradient's renders (use 1): a correlated one would bias the gradient of any loss not linear in the image\n";
    m.say(plan);
    m.explained = true;
  }
  if (g.stats.nonFinite > 0)
    throw Error("gradient: " + std::to_string(g.stats.nonFinite) + " non-finite contributions at iteration " + std::to_string(i));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - pilotSeconds;
  return out;
}

void Optimization::step(const Evaluation& evaluation) {
  Impl& m = *m_impl;
  const Experiment& e = m.e;
  const uint64_t i = m.iteration;
  if (evaluation.iteration != i || evaluation.theta != m.theta)
    throw Error("internal: an optimisation steps with the evaluation of its current iteration and θ");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double>& losses = evaluation.targetLosses;
  const std::vector<ImageSet>& estimates = evaluation.images;  // rank 0's alone when spread over processes
  if (i == 0 && m.root) {
    for (size_t t = 0; t < e.targets.size(); ++t) m.initialImages[t] = estimates[t];
    for (const TargetEntry& entry : m.entries)
      writeExr(m.initialImagePath(entry), entry.scan ? joinScanImages(e, entry, estimates) : estimates[entry.targets.front()]);
  }
  if (m.root && (i % e.imagesEvery == 0 || i + 1 == e.stop.iterations)) {
    std::vector<TargetImages> figures;
    for (size_t t = 0; t < e.targets.size(); ++t)
      figures.push_back({e.targets[t].name, m.setups[t].setup.gate, &m.targets[t], &m.initialImages[t], &estimates[t]});
    writeTargetFigures(m.run / "images", i, figures);
  }
  if (m.initialLoss.empty()) m.initialLoss = losses;
  std::vector<double> d = evaluation.gradient.theta;
  const double dataLoss = evaluation.loss;
  const double regularization = e.regularizers.empty() ? 0.0 : vktg::regularization(e, m.theta, d);
  const double loss = dataLoss + regularization;
  preconditionGradient(e, d);
  double norm = 0;
  for (double v : d) norm += v * v;
  norm = std::sqrt(norm);
  const std::optional<double> error = parameterError(e.parameters, m.theta);
  const double seconds = evaluation.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<double> row = {double(i), loss};
  for (const TargetEntry& entry : m.entries) {
    double entryLoss = 0;
    for (size_t t : entry.targets) entryLoss += losses[t];
    row.push_back(entryLoss);
  }
  if (!e.regularizers.empty()) row.push_back(regularization);
  row.push_back(norm);
  if (error) row.push_back(*error);
  row.push_back(seconds);
  if (m.root) m.log->append(row);
  m.lastLoss = loss;
  m.lastError = error;
  if (m.options.progress) {
    const double total0 = std::accumulate(m.initialLoss.begin(), m.initialLoss.end(), 0.0);
    char line[256];
    // The change is that of the image loss (the regulariser's share is in the log).
    std::snprintf(line, sizeof line, "iteration %llu/%u  loss %.4e (image loss %+.1f%%)  |grad| %.3e%s  %.2f s/it  ETA %s",
                  (unsigned long long)i, e.stop.iterations, loss, total0 > 0 ? 100.0 * (dataLoss / total0 - 1.0) : 0.0,
                  norm, error ? ("  error " + std::to_string(*error)).c_str() : "", seconds,
                  formatSeconds(seconds * double(e.stop.iterations - i - 1)).c_str());
    m.say(line);
  }
  m.optimizer->step(m.theta, d);
  if (!e.budget.finiteDifferences) m.adjoint.scale = evaluation.adjointScale;
  m.iteration = i + 1;
  std::string stop;
  if (e.stop.lossBelow && loss < *e.stop.lossBelow) stop = "the loss fell below stop.loss_below";
  if (e.stop.parameterErrorBelow && error && *error < *e.stop.parameterErrorBelow)
    stop = "the parameter error fell below stop.parameter_error_below";
  if (e.stop.seconds) {
    // Processes spread over a run stop together: by rank 0's clock.
    const double elapsed = m.collective ? broadcastDouble(*m.collective, m.elapsed()) : m.elapsed();
    if (elapsed > *e.stop.seconds) stop = "the run reached stop.seconds";
  }
  if (m.iteration == e.stop.iterations && stop.empty()) stop = kReachedIterations;
  m.stopReason = stop;
  if (m.iteration % e.checkpointEvery == 0 || !stop.empty()) checkpoint();
}

void Optimization::checkpoint() {
  if (!m_impl->root) return;  // rank 0 writes the run directory
  // θ and the optimiser state are those after the last completed iteration: a valid checkpoint.
  m_impl->writeState(m_impl->iteration, m_impl->elapsed());
  m_impl->writeFigures();
}

OptimizeSummary Optimization::finish() {
  Impl& m = *m_impl;
  if (m.stopReason.empty()) {
    m.stopReason = kReachedIterations;
    checkpoint();
  }
  OptimizeSummary summary;
  summary.iterations = m.iteration;
  summary.loss = m.lastLoss;
  summary.parameterError = m.lastError;
  summary.stopReason = m.stopReason;
  summary.seconds = m.elapsed();
  if (!m.root) return summary;
  writeParameters(m.run / "parameters.json", m.e, m.theta);
  writeOptimizedScene(m.run / "scene.json", m.e, m.theta);
  return summary;
}

OptimizeSummary optimize(VulkanContext& context, const OptimizeOptions& options) {
  Optimization run(context, options);
  try {
    while (!run.stopped()) run.step(run.evaluate());
  } catch (const Interrupted&) {
    run.checkpoint();
    throw;
  }
  return run.finish();
}

}  // namespace vktg
