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
#include <optional>
#include <string>

#include "host/vk_context.h"

namespace vktg {

struct OptimizeOptions {
  std::filesystem::path experiment;    // the experiment file (empty when resuming: the run's own)
  std::filesystem::path runDirectory;
  bool resume = false;                 // continue the run in runDirectory from its checkpoint
  bool force = false;                  // replace an existing run directory
  uint64_t memoryBudget = 0;  // 0: the device's default
  std::optional<uint32_t> iterations;  // overrides the experiment's stop.iterations
  std::function<void(const std::string&)> progress;  // one line per iteration (and a few more)
  bool explain = false;                // print the render and gradient plans once
};

struct OptimizeSummary {
  uint64_t iterations = 0;             // completed, in all (resumed runs included)
  double loss = 0;                     // of the last iteration
  std::optional<double> parameterError;
  double seconds = 0;                  // wall time, in all
  std::string stopReason;
};

// Throws vktg::Error for bad input (naming file, field and problem) before anything is written,
// and vktg::Interrupted after writing a checkpoint when SIGINT or SIGTERM arrives.
OptimizeSummary optimize(VulkanContext& context, const OptimizeOptions& options);

}  // namespace vktg
