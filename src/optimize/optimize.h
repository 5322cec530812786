// `vktg optimize`: inverse time-gated rendering (docs/optimize.md). Each iteration renders every
// target at the current θ with its own random numbers, forms the loss and its adjoint images,
// takes the loss gradient by adjoint renders of every derivative term (lossGradient: its cost does
// not grow with the number of parameters), adds the regularisers, preconditions, steps and projects.
// The scene stays on the device and moves in place (DeviceScene). Every random number of iteration
// i derives from (seed, i), the gradient accumulators are exact integers and the BVH follows from
// the θ it was last built at, so a run resumed from a checkpoint continues bit for bit as if it
// had never stopped.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "grad/collective.h"
#include "grad/gradient.h"
#include "vk/vk_context.h"
#include "vktg/image_io.h"

namespace vktg {

struct OptimizeOptions {
  std::filesystem::path experiment;    // the experiment file (empty when resuming: the run's own)
  std::filesystem::path runDirectory;
  bool resume = false;                 // continue the run in runDirectory from its checkpoint
  bool force = false;                  // replace an existing run directory
  uint64_t memoryBudget = 0;  // 0: the device's default
  std::optional<uint32_t> iterations;  // overrides the experiment's stop.iterations
  SceneDefines defines;                // a Mitsuba XML scene's $name values over the experiment's (a new run only)
  std::function<void(const std::string&)> progress;  // one line per iteration (and a few more)
  bool explain = false;                // print the render and gradient plans once
  // The processes the run is spread over (`mpirun`, docs/mpi.md): each renders its share of the
  // targets, all step identically, rank 0 alone writes the run directory. Null: one process.
  Collective* collective = nullptr;
};

struct OptimizeSummary {
  uint64_t iterations = 0;             // completed, in all (resumed runs included)
  double loss = 0;                     // of the last iteration
  std::optional<double> parameterError;
  double seconds = 0;                  // wall time, in all
  std::string stopReason;
};

// The loss and its gradient at one θ: what Optimization::evaluate returns and step consumes.
struct Evaluation {
  uint64_t iteration = 0;              // whose random numbers rendered it
  std::vector<double> theta;           // where
  std::vector<double> targetLosses;    // per target (the experiment's targets, a scan's points apart)
  double loss = 0;                     // the image loss: their sum (regularisers come in step)
  std::vector<ImageSet> images;        // per target: the image the loss was read from (spread over
                                       // processes: on rank 0, and only where step writes figures)
  LossGradient gradient;               // d loss / d θ of the image loss, with its plan and statistics
  double seconds = 0;                  // wall time, the term pilot's excluded (it runs once)
  // The gradient accumulators' scale after this gradient (it adapts to the gradient's size): the
  // run takes it on in step, so that evaluating twice at one iteration gives the same bits.
  double adjointScale = 0;
};

// An optimisation run, a step at a time: open a new run directory or resume one, evaluate the loss
// and its gradient at the current θ, step (regularisers, preconditioner, the optimiser, the log, the
// stop rules, checkpoints on their schedule), and finish. optimize() is this loop; other drivers
// (a process per device, a user's own loop) call the steps themselves.
class Optimization {
 public:
  // Checks everything about the input (naming file, field and problem) before the run directory
  // is touched, then prepares it (or reads it back, with options.resume) and synthesises the
  // targets that need it.
  Optimization(VulkanContext& context, const OptimizeOptions& options);
  ~Optimization();
  Optimization(const Optimization&) = delete;
  Optimization& operator=(const Optimization&) = delete;

  uint64_t iteration() const;                // iterations completed (resumed ones included)
  const std::vector<double>& theta() const;  // the current θ, in the experiment's parameter order
  std::vector<std::string> parameterNames() const;
  bool stopped() const;                      // a stop rule ended the run (stopReason says which)
  const std::string& stopReason() const;

  // The loss and gradient at the current θ with the current iteration's random numbers (the term
  // pilot runs first where the experiment asks and no earlier run did). Writes nothing but run.json
  // after the pilot. Throws vktg::Interrupted on SIGINT or SIGTERM.
  Evaluation evaluate();
  // Completes the iteration `evaluation` was rendered for: its images and log row, the step, the
  // stop rules, and a checkpoint where one is due or the run stopped.
  void step(const Evaluation& evaluation);
  // θ, the optimiser's state and the figures as of the last completed iteration.
  void checkpoint();
  // The final checkpoint, parameters.json and scene.json.
  OptimizeSummary finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

// Runs an optimisation to its end (Optimization's steps until a stop rule). Throws vktg::Error for
// bad input (naming file, field and problem) before anything is written, and vktg::Interrupted
// after writing a checkpoint when SIGINT or SIGTERM arrives.
OptimizeSummary optimize(VulkanContext& context, const OptimizeOptions& options);

}  // namespace vktg
