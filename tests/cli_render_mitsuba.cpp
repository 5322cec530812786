// `vktg render` of Mitsuba XML scenes: the default room as XML renders the JSON scene's image, an
// nlos_capture_meter renders its whole scan without a --scan file, and -D reaches the scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = VKTG_SOURCE_DIR;
const fs::path kRoomXml = kSource / "scenes" / "default_room.xml";
const fs::path kRoomJson = kSource / "scenes" / "cornell_box.json";
const fs::path kNlos = fs::path(VKTG_TEST_DATA) / "mitsuba" / "nlos_confocal.xml";

double meanOf(const ImageLayer& layer) {
  double sum = 0;
  for (float v : layer.pixels) sum += v;
  return sum / double(layer.pixels.size());
}

// The two files load to the same scene up to float rounding of the vertices (unit_mitsuba_xml), so
// their renders agree in mean: the image means over independent seeds pass a z-test. (Pixel by
// pixel at one seed they are not identical: the XML's transforms, composed in double, put the walls
// and the floor exactly where the JSON's float rotations leave them up to 1e-7, so the floor lies
// exactly in the plane of the boxes' bottoms, and a path that meets those edges and coincident
// faces can take another turn.)
TEST(CliRenderMitsuba, DefaultRoomXmlRendersTheJsonScenesImage) {
  TempDir dir;
  constexpr int kSeeds = 4;
  std::vector<double> meansXml, meansJson;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const fs::path xml = dir / ("xml" + std::to_string(seed) + ".exr"), json = dir / ("json" + std::to_string(seed) + ".exr");
    runVktgOk({"render", kRoomXml.string(), "-D", "spp=16", "--define=resolution=32", "--seed", std::to_string(seed),
               "--quiet", "--out", xml.string()},
              dir);
    runVktgOk({"render", kRoomJson.string(), "--spp", "16", "--resolution", "32x32", "--seed", std::to_string(seed),
               "--quiet", "--out", json.string()},
              dir);
    const ImageSet a = readExr(xml), b = readExr(json);
    ASSERT_EQ(a.width, 32u);
    ASSERT_EQ(a.height, 32u);
    ASSERT_EQ(a.layers.size(), 1u);
    ASSERT_EQ(b.layers.size(), 1u);
    meansXml.push_back(meanOf(a.layers[0]));
    meansJson.push_back(meanOf(b.layers[0]));
  }
  auto meanAndError = [](const std::vector<double>& v) {
    double m = 0, s = 0;
    for (double x : v) m += x / double(v.size());
    for (double x : v) s += (x - m) * (x - m) / double(v.size() - 1);
    return std::pair(m, std::sqrt(s / double(v.size())));
  };
  const auto [mx, ex] = meanAndError(meansXml);
  const auto [mj, ej] = meanAndError(meansJson);
  EXPECT_GT(mx, 0.0);
  EXPECT_GT(ex, 0.0) << "independent seeds must differ";
  EXPECT_LT(std::abs(mx - mj), 4.0 * std::sqrt(ex * ex + ej * ej)) << mx << " +- " << ex << " vs " << mj << " +- " << ej;
}

TEST(CliRenderMitsuba, CaptureMeterRendersItsWholeScan) {
  TempDir dir;
  const fs::path exr = dir / "cube.exr";
  const CliResult r = runVktgOk({"render", kNlos.string(), "-D", "spp=8", "--out", exr.string()}, dir);
  EXPECT_NE(r.err.find("64 scan views (8 x 8)"), std::string::npos) << r.describe();
  const ImageSet cube = readExr(exr);
  EXPECT_EQ(cube.width, 8u);
  EXPECT_EQ(cube.height, 8u);
  ASSERT_EQ(cube.layers.size(), 20u);
  double total = 0;
  for (const ImageLayer& layer : cube.layers)
    for (float v : layer.pixels) {
      ASSERT_TRUE(std::isfinite(v) && v >= 0) << layer.name;
      total += v;
    }
  EXPECT_GT(total, 0.0) << "the hidden object returns light within the bins";
  // Nothing returns before twice the wall's distance to the ridge (0.9 m): the first bins are dark.
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(meanOf(cube.layers[k]), 0.0) << cube.layers[k].name;
  // -D changes the grid.
  const fs::path small = dir / "small.exr";
  runVktgOk({"render", kNlos.string(), "-Dgrid=3", "-D", "spp=2", "--quiet", "--out", small.string()}, dir);
  EXPECT_EQ(readExr(small).width, 3u);
  // The meter's scan as a capture file, without a --scan.
  runVktgOk({"render", kNlos.string(), "-Dgrid=3", "-D", "spp=2", "--quiet", "--out", (dir / "small.hdf5").string()}, dir);
  EXPECT_GT(fs::file_size(dir / "small.hdf5"), 0u);
}

TEST(CliRenderMitsuba, DefineErrors) {
  TempDir dir;
  const fs::path out = dir / "x.exr";
  CliResult r = runVktg({"render", kRoomXml.string(), "-D", "spp", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 2) << r.describe();
  EXPECT_NE(r.err.find("NAME=VALUE"), std::string::npos) << r.describe();
  r = runVktg({"render", kRoomXml.string(), "-D", "spp=1", "-D", "spp=2", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 2) << r.describe();
  EXPECT_NE(r.err.find("defined twice"), std::string::npos) << r.describe();
  r = runVktg({"render", kRoomXml.string(), "-D", "sp=1", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  EXPECT_NE(r.err.find(kRoomXml.string() + ": -D sp: the scene uses no $sp"), std::string::npos) << r.describe();
  r = runVktg({"render", kRoomJson.string(), "-D", "spp=1", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  EXPECT_NE(r.err.find("Mitsuba XML"), std::string::npos) << r.describe();
  // grad and fd take -D too (the XML scene has no parameters to differentiate).
  r = runVktg({"grad", kRoomXml.string(), "-D", "spp=1", "--param", "x", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  EXPECT_NE(r.err.find("x"), std::string::npos) << r.describe();
  EXPECT_EQ(r.err.find("-D"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(out));
}

// optimize passes -D to its experiment's scene (a resumed run keeps the defines it started with);
// bench takes them for the scene file of `bench trace` only.
TEST(CliRenderMitsuba, OptimizeAndBenchTakeDefines) {
  TempDir dir;
  const fs::path experiment = fs::path(VKTG_SOURCE_DIR) / "experiments" / "confocal_scan" / "fine_bins.experiment.json";
  CliResult r = runVktg({"optimize", experiment.string(), "--out", (dir / "run").string(), "-D", "a=1"});
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  EXPECT_NE(r.err.find("-D a: defines apply to Mitsuba XML scenes only"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir / "run"));
  r = runVktg({"optimize", "--resume", (dir / "run").string(), "-D", "a=1"});
  EXPECT_EQ(r.exitCode, 2) << r.describe();
  EXPECT_NE(r.err.find("no -D"), std::string::npos) << r.describe();
  r = runVktg({"bench", "render", "-D", "a=1"});
  EXPECT_EQ(r.exitCode, 2) << r.describe();
  EXPECT_NE(r.err.find("takes no scene file"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace vktg::test
