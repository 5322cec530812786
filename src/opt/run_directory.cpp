#include "opt/run_directory.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "opt/plot.h"
#include "vktg/error.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// Files and folders a run writes; --force removes exactly these.
const char* const kRunEntries[] = {"experiment.json", "run.json", "log.csv", "checkpoint.bin", "loss.png",
                                   "parameter_error.png", "parameters.json", "scene.json", "images", "targets",
                                   "report.md"};

bool isRunEntry(const fs::path& name) {
  const std::string n = name.string();
  for (const char* entry : kRunEntries)
    if (n == entry) return true;
  return n.rfind("heightfield_", 0) == 0 && name.extension() == ".png";
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string(), "", "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void requireWritable(const fs::path& directory) {
  if (::access(directory.c_str(), W_OK | X_OK) != 0)
    fail(directory.string(), "", "the run directory is not writable");
}

}  // namespace

void prepareRunDirectory(const fs::path& directory, bool force) {
  std::error_code ec;
  const std::string name = directory.string();
  if (fs::exists(directory, ec)) {
    if (!fs::is_directory(directory, ec)) fail(name, "", "exists and is not a directory");
    std::vector<fs::path> entries;
    for (const fs::directory_entry& e : fs::directory_iterator(directory, ec)) entries.push_back(e.path().filename());
    if (!force && !entries.empty())
      fail(name, "", "the run directory exists: continue it with --resume, or replace it with --force");
    for (const fs::path& entry : entries)
      if (!isRunEntry(entry))
        fail(name, "", "--force replaces run directories only, and '" + entry.string() +
                           "' is no file of a run: choose another directory");
    requireWritable(directory);
    for (const fs::path& entry : entries) fs::remove_all(directory / entry, ec);
  } else {
    fs::create_directories(directory, ec);
    if (ec) fail(name, "", "cannot create the run directory: " + ec.message());
  }
  requireWritable(directory);
  fs::create_directories(directory / "images", ec);
  fs::create_directories(directory / "targets", ec);
  if (ec) fail(name, "", "cannot create its subdirectories: " + ec.message());
}

void checkResumableRun(const fs::path& directory) {
  const std::string name = directory.string();
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) fail(name, "", "--resume: no run directory here");
  for (const char* file : {"run.json", "experiment.json", "checkpoint.bin"})
    if (!fs::exists(directory / file, ec))
      fail(name, "", std::string("--resume: the run directory has no ") + file + " (was it made by vktg optimize?)");
  requireWritable(directory);
}

void writeRunInfo(const fs::path& directory, const RunInfo& info) {
  nlohmann::json j;
  j["experiment"] = fs::absolute(info.experiment).lexically_normal().string();
  j["memory_budget"] = info.memoryBudget;
  if (!info.defines.empty()) j["defines"] = info.defines;
  if (info.pilotDone)
    j["term_pilot"] = {{"spp_edge", info.pilotSppEdge},
                       {"spp_boundary", info.pilotSppBoundary},
                       {"spp_boundary_camera", info.pilotSppBoundaryCamera}};
  writeFileAtomic(directory / "run.json", j.dump(2) + "\n");
}

RunInfo readRunInfo(const fs::path& directory) {
  const fs::path path = directory / "run.json";
  RunInfo info;
  try {
    nlohmann::json j = nlohmann::json::parse(readText(path));
    info.experiment = j.at("experiment").get<std::string>();
    info.memoryBudget = j.at("memory_budget").get<uint64_t>();
    if (j.contains("defines")) info.defines = j.at("defines").get<SceneDefines>();
    if (j.contains("term_pilot")) {
      info.pilotSppEdge = j.at("term_pilot").at("spp_edge").get<double>();
      info.pilotSppBoundary = j.at("term_pilot").at("spp_boundary").get<double>();
      // Runs from before the pilot timed the camera's connections apart gave them the boundary's.
      info.pilotSppBoundaryCamera = j.at("term_pilot").value("spp_boundary_camera", info.pilotSppBoundary);
      for (const auto& [field, spp] : {std::pair{"spp_edge", info.pilotSppEdge}, std::pair{"spp_boundary", info.pilotSppBoundary},
                                       std::pair{"spp_boundary_camera", info.pilotSppBoundaryCamera}})
        if (!(spp >= 0 && spp <= double(1u << 24)))
          fail(path.string(), std::string("term_pilot.") + field, "must be a number of samples per pixel in [0, 2^24]");
      info.pilotDone = true;
    }
  } catch (const nlohmann::json::exception& e) {
    fail(path.string(), "", std::string("malformed run information: ") + e.what());
  }
  return info;
}

std::map<std::string, std::vector<double>> readLogColumns(const fs::path& path) {
  std::map<std::string, std::vector<double>> columns;
  std::ifstream in(path);
  if (!in) return columns;
  std::string line;
  std::vector<std::string> names;
  if (std::getline(in, line)) {
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  }
  while (std::getline(in, line)) {
    std::stringstream row(line);
    size_t c = 0;
    for (std::string field; std::getline(row, field, ',') && c < names.size(); ++c)
      columns[names[c]].push_back(std::strtod(field.c_str(), nullptr));
  }
  return columns;
}

void writeParameters(const fs::path& path, const Experiment& experiment, const std::vector<double>& theta) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (size_t k = 0; k < experiment.parameters.size(); ++k) {
    const ExperimentParameter& p = experiment.parameters[k];
    nlohmann::ordered_json entry;
    entry["name"] = p.name;
    entry["initial"] = p.initial;
    entry["final"] = theta.at(k);
    if (p.truth) entry["truth"] = *p.truth;
    out.push_back(entry);
  }
  writeFileAtomic(path, out.dump(2) + "\n");
}

bool writeOptimizedScene(const fs::path& path, const Experiment& experiment, const std::vector<double>& theta) {
  if (experiment.scenePath.extension() != ".json") return false;
  nlohmann::ordered_json scene = nlohmann::ordered_json::parse(readText(experiment.scenePath));
  std::map<std::string, double> values;
  for (size_t k = 0; k < experiment.parameters.size(); ++k) values[experiment.parameters[k].name] = theta.at(k);
  for (nlohmann::ordered_json& p : scene["parameters"]) {
    const std::string shapeName = p.value("shape", "");
    const VertexExpansion expansion = vertexExpansion(p.value("type", ""), shapeName);
    if (!expansion.suffixes.empty()) {
      // Every expanded parameter the experiment optimised, at its place in `values`.
      const auto shape = std::find_if(experiment.scene.shapes.begin(), experiment.scene.shapes.end(),
                                      [&](const Shape& s) { return s.name == shapeName; });
      const size_t count = shape == experiment.scene.shapes.end() ? 0 : shape->positions.size() * expansion.suffixes.size();
      const std::string prefix = p.value("name_prefix", expansion.defaultPrefix);
      for (size_t i = 0; i < count; ++i) {
        const size_t vertex = i / expansion.suffixes.size();
        auto it = values.find(prefix + std::to_string(vertex) + expansion.suffixes[i % expansion.suffixes.size()]);
        if (it == values.end()) continue;
        nlohmann::ordered_json& list = p["values"];
        if (list.is_null()) list = nlohmann::ordered_json::array();
        while (list.size() < count) list.push_back(0.0);
        list[i] = list[i].get<double>() + it->second;
      }
    } else if (auto it = values.find(p.value("name", "")); it != values.end()) {
      p["value"] = p.value("value", 0.0) + it->second;
    }
  }
  // Mesh files are relative to the scene's folder, which is not the run's.
  const fs::path base = fs::absolute(experiment.scenePath).parent_path();
  for (nlohmann::ordered_json& shape : scene["shapes"])
    if (shape.value("type", "") == "mesh" && shape.contains("file"))
      shape["file"] = (base / shape["file"].get<std::string>()).lexically_normal().string();
  writeFileAtomic(path, scene.dump(2) + "\n");
  return true;
}

void writeRunFigures(const fs::path& directory, const Experiment& experiment,
                     const std::map<std::string, std::vector<double>>& log, const std::vector<double>& theta) {
  auto column = [&](const std::string& name) {
    auto it = log.find(name);
    return it == log.end() ? std::vector<double>{} : it->second;
  };
  const std::vector<double> iterations = column("iteration");
  if (iterations.empty()) return;
  // One line per "targets" entry (a scan's: the sum over its points) while the legend fits and the
  // colours stay distinct; beyond that the entries keep their losses in log.csv only.
  constexpr size_t kMaxTargetLines = 8;
  const std::vector<TargetEntry> entries = targetEntries(experiment);
  const bool perEntry = entries.size() > 1 && entries.size() <= kMaxTargetLines;
  LinePlot loss{entries.size() <= kMaxTargetLines ? "Loss" : "Loss (" + std::to_string(entries.size()) + " targets: each in log.csv)",
                "iteration", "loss", true, {}};
  loss.series.push_back({"total", iterations, column("loss")});
  if (perEntry)
    for (const TargetEntry& entry : entries) loss.series.push_back({entry.name, iterations, column("loss_" + entry.name)});
  if (log.count("regularization")) loss.series.push_back({"regularization", iterations, column("regularization")});
  writeLinePlot(directory / "loss.png", loss);
  if (log.count("parameter_error")) {
    LinePlot error{"Parameter error (RMS of theta - truth)", "iteration", "parameter error", true, {}};
    error.series.push_back({"", iterations, column("parameter_error")});
    writeLinePlot(directory / "parameter_error.png", error);
  }
  // Heightfields whose every height is optimised with a known truth (one parameter per vertex: a
  // vertex moved along several directions has no one height to draw).
  for (uint32_t s = 0; s < experiment.scene.shapes.size(); ++s) {
    const Shape& shape = experiment.scene.shapes[s];
    if (shape.grid.x == 0) continue;
    const size_t count = size_t(shape.grid.x) * shape.grid.y;
    std::vector<double> recovered(count, 0.0), truth(count, 0.0);
    std::vector<uint32_t> seen(count, 0);
    for (size_t k = 0; k < experiment.parameters.size(); ++k) {
      const ExperimentParameter& ep = experiment.parameters[k];
      const Parameter& p = experiment.scene.parameters[ep.sceneIndex];
      if (p.kind != ParameterKind::Displace || p.target != shape.name || p.vertices.size() != 1 || !ep.truth) continue;
      const uint32_t v = p.vertices[0];
      recovered[v] = theta[k];
      truth[v] = *ep.truth;
      ++seen[v];
    }
    if (std::count(seen.begin(), seen.end(), 1u) != std::ptrdiff_t(count)) continue;
    writeHeightfieldComparison(directory / ("heightfield_" + shape.name + ".png"), shape.grid.x, shape.grid.y, recovered,
                               truth);
  }
}

}  // namespace vktg
