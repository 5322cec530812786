// tools/make_confocal_scan.py writes the confocal-scan experiment at any size: at the repository's
// size (8 x 8 heights, 8 x 8 scan) it must write exactly experiments/confocal_scan, and at 100 x 100
// it scales the large-steps lambda with the square of the resolution (docs/experiments.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// Runs the script into a fresh directory under the system's temporary one.
fs::path generate(const std::string& name, const std::string& arguments) {
  const fs::path out = fs::temp_directory_path() / ("vktg-confocal-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(out);
  const fs::path script = fs::path(VKTG_SOURCE_DIR) / "tools" / "make_confocal_scan.py";
  // The interpreter is not built with the project: in a sanitizer build the ASan runtime this
  // binary runs under (LD_PRELOAD) would follow it and report the interpreter's own allocations.
  const std::string command =
      "env -u LD_PRELOAD /usr/bin/python3 '" + script.string() + "' '" + out.string() + "' " + arguments;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return out;
}

TEST(MakeConfocalScan, WritesTheRepositorysExperimentAtItsSize) {
  const fs::path out = generate("repo", "");
  const fs::path repo = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan";
  for (const char* file : {"scene.json", "scan.json", "fine_bins.experiment.json", "coarse_bins.experiment.json"})
    EXPECT_EQ(readAll(out / file), readAll(repo / file)) << file;
  fs::remove_all(out);
}

TEST(MakeConfocalScan, ScalesTheLargeStepsLambdaWithTheResolution) {
  const fs::path out = generate("large", "--heights 100 --scan 4");
  const std::string experiment = readAll(out / "fine_bins.experiment.json");
  EXPECT_NE(experiment.find("\"lambda\": 800"), std::string::npos);
  fs::remove_all(out);
}

}  // namespace
