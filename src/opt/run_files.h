// Files of a `vktg optimize` run directory: the CSV log and checkpoints. Checkpoints are written
// atomically and read back exactly (doubles round-trip bit for bit), so a resumed run continues as
// if it had not stopped.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "opt/optimizer.h"

namespace vktg {

// log.csv: a header line, then one line per iteration, appended and flushed as it comes. Opening
// an existing log for a resumed run keeps its first `keepRows` data rows and drops the rest (rows
// written after the checkpoint the run resumes from). Column names must fit a CSV header (no
// commas, quotes or line breaks). Throws vktg::Error naming the file when a resumed log's header
// differs from `columns`, it holds fewer than `keepRows` complete rows, a kept row has the wrong
// number of fields, or a write fails. A last line without its line break (a write cut short) is
// not a complete row.
class RunLog {
 public:
  RunLog(const std::filesystem::path& path, const std::vector<std::string>& columns, bool resume, uint64_t keepRows);
  void append(const std::vector<double>& values);  // one per column; doubles printed with 17 digits

 private:
  std::filesystem::path m_path;
  size_t m_columns;
};

struct Checkpoint {
  uint64_t iteration = 0;                 // iterations completed
  std::vector<std::string> names;         // parameter names, in order
  std::vector<double> theta;
  OptimizerState optimizer;
  std::vector<double> bvhTheta;           // θ of the scene the device BVH was last built from
  double seconds = 0;                     // wall time spent so far
  double adjointScale = 0;                // fixed-point scale of the gradient accumulators (0: not chosen)
  std::vector<double> initialLoss;        // per target, for relative reporting
};

// Format (docs/optimize.md "Checkpoints"): a versioned little-endian binary file with a magic,
// counts, the names, the doubles bit for bit, and a checksum.
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
// Throws vktg::Error naming the file for a missing, truncated or malformed checkpoint.
Checkpoint readCheckpoint(const std::filesystem::path& path);
// Throws vktg::Error naming the checkpoint file unless it was written for this experiment: the
// same parameter names in the same order, and one initial loss per target (none before iteration 1).
void checkCheckpointMatches(const std::filesystem::path& path, const Checkpoint& checkpoint, const Experiment& experiment);

}  // namespace vktg
