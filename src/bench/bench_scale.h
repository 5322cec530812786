// `vktg bench scale` (docs/benchmarks.md, "Scaling over processes"): an optimisation's time per
// iteration and the share of it spent in the gradient's all-reduce, for the processes it runs
// under (`mpirun -np N vktg bench scale`), one row per N in scale.csv; and a model of strong and
// weak scaling from those rows and the all-reduce's message size (8 bytes per accumulator).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "grad/collective.h"
#include "vk/vk_context.h"

namespace vktg {

struct BenchScaleOptions {
  std::filesystem::path experiment;  // the optimisation timed
  std::filesystem::path outDir;      // scale.csv and table.md; the run directories under it
  uint32_t iterations = 4;           // timed after one untimed iteration (pipelines, first scale)
  uint64_t memoryBudget = 0;
  Collective* collective = nullptr;  // the processes (null: one, without mpirun)
};

struct BenchScaleRow {
  int processes = 1;
  uint64_t targets = 0, parameters = 0;
  uint64_t allReduceBytes = 0;  // per all-reduce of the gradient accumulators
  double iterationSeconds = 0;  // median over the timed iterations, rank 0's
  double allReduceSeconds = 0;  // of which in the accumulators' all-reduce (waiting for peers included)
  double exchangeSeconds = 0;   // in every exchange, the all-reduce's included
};

// Runs the optimisation (every process; collective), returns rank 0's row.
BenchScaleRow benchScale(VulkanContext& context, const BenchScaleOptions& options);
// Adds the row to outDir/scale.csv (replacing one of the same process count) and writes table.md:
// the measured rows and the model's predictions. Rank 0 only.
void writeBenchScaleReport(const BenchScaleRow& row, const BenchScaleOptions& options, const std::string& command);

}  // namespace vktg
