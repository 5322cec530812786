// End-to-end tests of `vktg render` / `vktg info` / `--help`: the binary is run as a user would
// run it (tests/support/cli_runner.h), always with VKTG_VALIDATION=1, so any Vulkan validation
// message makes it exit 3 and fails the test. Images are tiny (16x16, 1-2 spp): these tests check
// the plumbing (files, layers, shapes, messages, reproducibility), not the image values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <regex>
#include <sstream>

#include "support/cli_runner.h"
#include "vktg/gate.h"
#include "vktg/image_io.h"
#include "vktg/scene.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;

// Runs a command that must succeed, with the working directory in `dir` so that nothing lands
// in the source tree.
void expectFiniteNonNegative(const ImageSet& images) {
  for (const ImageLayer& layer : images.layers)
    for (size_t i = 0; i < layer.pixels.size(); ++i) {
      ASSERT_TRUE(std::isfinite(layer.pixels[i]) && layer.pixels[i] >= 0.0f)
          << "layer '" << layer.name << "' pixel " << i << " = " << layer.pixels[i];
    }
}

// A parsed .npy file (format 1.0, as numpy.save writes it).
struct Npy {
  std::string descr;
  bool fortranOrder = true;
  std::vector<size_t> shape;
  std::vector<float> data;
};

Npy readNpy(const fs::path& path) {
  const std::string bytes = readFileBytes(path);
  Npy npy;
  if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0) {
    ADD_FAILURE() << path << " does not start with the .npy magic";
    return npy;
  }
  const size_t headerLength = size_t(uint8_t(bytes[8])) | (size_t(uint8_t(bytes[9])) << 8);
  EXPECT_EQ((10 + headerLength) % 64, 0u) << "the .npy header must pad the data to 64 bytes";
  const std::string header = bytes.substr(10, headerLength);
  std::smatch m;
  if (std::regex_search(header, m, std::regex("'descr':\\s*'([^']*)'"))) npy.descr = m[1];
  npy.fortranOrder = header.find("'fortran_order': False") == std::string::npos;
  if (std::regex_search(header, m, std::regex("'shape':\\s*\\(([^)]*)\\)"))) {
    std::stringstream dims(m[1].str());
    std::string item;
    while (std::getline(dims, item, ','))
      if (item.find_first_not_of(' ') != std::string::npos) npy.shape.push_back(std::stoul(item));
  }
  const size_t dataBytes = bytes.size() - 10 - headerLength;
  npy.data.resize(dataBytes / 4);
  std::memcpy(npy.data.data(), bytes.data() + 10 + headerLength, npy.data.size() * 4);
  EXPECT_EQ(dataBytes % 4, 0u);
  return npy;
}

// "12.5" seconds somewhere in a line about time: the summary must say how long the run took.
bool mentionsSeconds(const std::string& text) { return std::regex_search(text, std::regex("[0-9.]+ s\\b")); }

TEST(CliRender, DefaultSceneWritesExrAndPngAndSaysWhereAndHowLong) {
  TempDir dir;
  const fs::path exr = dir / "image.exr";
  CliResult r = runVktgOk({"render", "--spp", "2", "--resolution", "16x16", "--out", exr.string()}, dir);
  ASSERT_TRUE(fs::is_regular_file(exr)) << r.describe();
  const fs::path png = dir / "image.png";
  ASSERT_TRUE(fs::is_regular_file(png)) << r.describe();
  EXPECT_EQ(readFileBytes(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(r.err.find(exr.string()), std::string::npos) << "the summary must name the EXR\n" << r.describe();
  EXPECT_NE(r.err.find(png.string()), std::string::npos) << "the summary must name the PNG\n" << r.describe();
  EXPECT_TRUE(mentionsSeconds(r.err)) << "the summary must say how long the render took\n" << r.describe();

  ImageSet images = readExr(exr);
  EXPECT_EQ(images.width, 16u);
  EXPECT_EQ(images.height, 16u);
  ASSERT_EQ(images.layers.size(), 1u);
  ASSERT_EQ(images.layers[0].pixels.size(), 256u);
  expectFiniteNonNegative(images);
  // The default scene's box gate spans the direct and first-bounce lengths: it is not black.
  double sum = 0;
  for (float v : images.layers[0].pixels) sum += v;
  EXPECT_GT(sum, 0.0);
  // Only the requested outputs, nothing else (no default out/ directory).
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"image.exr", "image.png"}));
}

TEST(CliRender, QuietPrintsNothingOnStderr) {
  TempDir dir;
  CliResult r = runVktgOk({"render", "--spp", "1", "--resolution", "8x8", "--quiet", "--out", (dir / "q.exr").string()}, dir);
  EXPECT_EQ(r.err, "") << r.describe();
  EXPECT_TRUE(fs::is_regular_file(dir / "q.exr"));
}

TEST(CliRender, TransientStackIsMultiLayerExrNamedByBinAndNpyOfShapeHWT) {
  TempDir dir;
  const fs::path exr = dir / "stack.exr";
  CliResult r = runVktgOk({"render", "--spp", "2", "--resolution", "16x12", "--gate", "bins:3,0.5,6", "--npy", "--out",
                       exr.string()},
                      dir);
  ASSERT_TRUE(fs::is_regular_file(exr)) << r.describe();
  EXPECT_TRUE(fs::is_regular_file(dir / "stack.png"));
  ASSERT_TRUE(fs::is_regular_file(dir / "stack.npy")) << r.describe();

  const Gate gate = parseGateSpec("bins:3,0.5,6");
  ImageSet images = readExr(exr);
  EXPECT_EQ(images.width, 16u);
  EXPECT_EQ(images.height, 12u);
  ASSERT_EQ(images.layers.size(), 6u);
  for (uint32_t k = 0; k < 6; ++k) {
    EXPECT_EQ(images.layers[k].name, gate.layerName(k));
    // The name carries the bin's range "LO-HI" at its end (metres).
    std::smatch m;
    ASSERT_TRUE(std::regex_search(images.layers[k].name, m, std::regex("([0-9.]+)-([0-9.]+)$")))
        << images.layers[k].name;
    EXPECT_NEAR(std::stod(m[1]), 3.0 + 0.5 * k, 1e-6) << images.layers[k].name;
    EXPECT_NEAR(std::stod(m[2]), 3.5 + 0.5 * k, 1e-6) << images.layers[k].name;
  }
  expectFiniteNonNegative(images);

  Npy npy = readNpy(dir / "stack.npy");
  EXPECT_EQ(npy.descr, "<f4");
  EXPECT_FALSE(npy.fortranOrder);
  ASSERT_EQ(npy.shape, (std::vector<size_t>{12, 16, 6}));
  ASSERT_EQ(npy.data.size(), 12u * 16u * 6u);
  // Same numbers as the EXR, element (y, x, k) in C order.
  for (uint32_t y = 0; y < 12; ++y)
    for (uint32_t x = 0; x < 16; ++x)
      for (uint32_t k = 0; k < 6; ++k)
        ASSERT_EQ(npy.data[(size_t(y) * 16 + x) * 6 + k], images.layers[k].pixels[size_t(y) * 16 + x])
            << "y " << y << " x " << x << " bin " << k;
}

TEST(CliRender, HelpOfEveryCommandExitsZero) {
  TempDir dir;
  CliResult top = runVktgOk({"--help"}, dir);
  EXPECT_NE(top.out.find("usage: vktg"), std::string::npos) << top.describe();
  // Every command the top-level help lists (lines "  NAME  summary" after "commands:").
  std::vector<std::string> commands;
  std::istringstream lines(top.out.substr(std::min(top.out.size(), top.out.find("commands:"))));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_match(line, m, std::regex("  ([a-z]+)\\s+.*"))) commands.push_back(m[1]);
  }
  ASSERT_FALSE(commands.empty()) << top.describe();
  EXPECT_NE(std::find(commands.begin(), commands.end(), "render"), commands.end());
  EXPECT_NE(std::find(commands.begin(), commands.end(), "info"), commands.end());
  for (const std::string& command : commands) {
    SCOPED_TRACE("vktg " + command + " --help");
    CliResult r = runVktgOk({command, "--help"}, dir);
    EXPECT_NE(r.out.find("usage: vktg " + command), std::string::npos) << r.describe();
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(CliRender, InfoListsAUsableDevice) {
  TempDir dir;
  CliResult r = runVktgOk({"info"}, dir);
  EXPECT_NE(r.out.find("usable by vktg: yes"), std::string::npos) << r.describe();
}

TEST(CliRender, ExplainPrintsThePlan) {
  TempDir dir;
  CliResult r = runVktgOk({"render", "--spp", "1", "--resolution", "8x8", "--gate", "box:3.5,4.5", "--explain", "--out",
                       (dir / "e.exr").string()},
                      dir);
  EXPECT_NE(r.out.find("plan"), std::string::npos) << r.describe();
  // One reason per choice: the NEE strategy and where paths end for this gate.
  EXPECT_NE(r.out.find("NEE"), std::string::npos) << r.describe();
  EXPECT_NE(r.out.find("4.5"), std::string::npos) << "the cutoff at the gate's end must be explained\n" << r.describe();
}

TEST(CliRender, ExplainShowsThePilotThatChoseTheEstimatorOrWhyNone) {
  TempDir dir;
  const std::vector<std::string> base = {"render", "--resolution", "4x4", "--gate", "gaussian:5,0.05", "--explain",
                                         "--quiet", "--out", (dir / "p.exr").string()};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return runVktgOk(args, dir).out;
  };
  // A 4x4 render is mostly launch cost: nine pilot renders would cost more than a quarter of it.
  const std::string stopped = with({"--spp", "256"});
  EXPECT_NE(stopped.find("no pilot: with"), std::string::npos) << stopped;
  EXPECT_NE(stopped.find("more than 25% of it"), std::string::npos) << stopped;
  const std::string piloted = with({"--spp", "256", "--pilot", "on"});
  EXPECT_NE(piloted.find("from a pilot of 8 spp per estimator"), std::string::npos) << piloted;
  for (const char* estimator : {"standard ", "ellipsoidal ", "mis "})
    EXPECT_NE(piloted.find(std::string("  ") + estimator), std::string::npos) << "no pilot line for " << estimator << "\n" << piloted;
  EXPECT_NE(piloted.find("relMSE x time"), std::string::npos) << piloted;
  const std::string small = with({"--spp", "64", "--pilot", "on"});
  EXPECT_NE(small.find("no pilot: 64 spp is too few"), std::string::npos) << small;
  const std::string ruled = with({"--spp", "256", "--pilot", "off"});
  EXPECT_EQ(ruled.find("pilot"), std::string::npos) << ruled;
  EXPECT_NE(ruled.find("path-length spread"), std::string::npos) << "the rule decides\n" << ruled;
  CliResult bad = runVktg({"render", "--pilot", "sometimes", "--out", (dir / "q.exr").string()}, {.cwd = dir.path()});
  EXPECT_NE(bad.exitCode, 0) << bad.describe();
  EXPECT_NE(bad.err.find("--pilot: 'sometimes' is not one of auto, on, off"), std::string::npos) << bad.describe();
}

TEST(CliRender, SameSeedGivesIdenticalImagesAndAnotherSeedDoesNot) {
  TempDir dir;
  auto render = [&](const std::string& name, const std::string& seed) {
    runVktgOk({"render", "--spp", "2", "--resolution", "16x16", "--seed", seed, "--quiet", "--out", (dir / name).string()},
          dir);
    return readFileBytes(dir / name);
  };
  const std::string a = render("a.exr", "7"), b = render("b.exr", "7"), c = render("c.exr", "8");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "two renders with --seed 7 differ";
  // The comparison above means something only if the seed reaches the sampler.
  EXPECT_NE(readExr(dir / "a.exr").layers[0].pixels, readExr(dir / "c.exr").layers[0].pixels)
      << "--seed 7 and --seed 8 give the same image";
}

TEST(CliRender, ExampleScenesRender) {
  const fs::path scenes = fs::path(VKTG_SOURCE_DIR) / "scenes";
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(scenes))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no example scenes in " << scenes;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    TempDir dir;
    std::vector<std::string> args = {"render", file.string(), "--spp", "1", "--out", (dir / "x.exr").string()};
    // A point sensor is one pixel and refuses --resolution; cameras keep the test small otherwise.
    if (loadScene(file).camera.type == CameraType::Perspective) {
      args.push_back("--resolution");
      args.push_back("16x16");
    }
    runVktgOk(args, dir);
    ASSERT_TRUE(fs::is_regular_file(dir / "x.exr"));
    expectFiniteNonNegative(readExr(dir / "x.exr"));
  }
}

}  // namespace
}  // namespace vktg::test
