// The run directory of `vktg optimize` (docs/optimize.md "Run directory"): making or reopening it,
// what a resumed run needs to know of the original one (run.json), and the files a run writes
// besides its log and checkpoints: the optimised parameters, the scene with them, the plots.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "opt/experiment.h"

namespace vktg {

// What a resumed run takes from the original: where the experiment came from (relative paths in it
// resolve from there) and the memory budget (which fixes the batch sizes, hence the summation order).
struct RunInfo {
  std::filesystem::path experiment;
  uint64_t memoryBudget = 0;
  SceneDefines defines;  // `vktg optimize -D`: a resumed run loads its scene with the same
  // Samples of the edge and path-length-boundary terms that the term pilot chose ("spp_edge",
  // "spp_boundary" or "spp_boundary_camera": "auto"; 0 where it has not run or the term keeps the
  // experiment's): measured once, so that a resumed run uses the original's.
  double pilotSppEdge = 0, pilotSppBoundary = 0, pilotSppBoundaryCamera = 0;
  bool pilotDone = false;
};

// A fresh run: creates `directory`. Fails without touching anything when it exists (unless
// `force`, and then only when it is empty or holds a previous run, whose files are removed) or
// when it cannot be created or written.
void prepareRunDirectory(const std::filesystem::path& directory, bool force);
// A resumed run: fails unless `directory` holds a run (run.json, experiment.json, checkpoint.bin).
void checkResumableRun(const std::filesystem::path& directory);

void writeRunInfo(const std::filesystem::path& directory, const RunInfo& info);
RunInfo readRunInfo(const std::filesystem::path& directory);

// The columns of a log.csv, by name (a resumed run's plots cover its whole history).
std::map<std::string, std::vector<double>> readLogColumns(const std::filesystem::path& path);

// parameters.json: per parameter its name, initial value, final value and truth.
void writeParameters(const std::filesystem::path& path, const Experiment& experiment, const std::vector<double>& theta);
// scene.json: the experiment's scene file with every optimised parameter's `value` (heightfield
// heights: `values`) set to θ (added to a value it already had), mesh paths made absolute. Only JSON
// scenes can be rewritten; for a glTF scene this returns false and writes nothing.
bool writeOptimizedScene(const std::filesystem::path& path, const Experiment& experiment, const std::vector<double>& theta);

// loss.png and parameter_error.png from the log's columns; heightfield_<shape>.png for every
// heightfield whose heights are all optimised with a known truth.
void writeRunFigures(const std::filesystem::path& directory, const Experiment& experiment,
                     const std::map<std::string, std::vector<double>>& log, const std::vector<double>& theta);

}  // namespace vktg
