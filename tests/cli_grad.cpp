// End-to-end: `vktg grad` with the edge pass: the outputs --split-terms promises, the plan
// --explain prints for parameters that do and do not move geometry, and bad --terms lists.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;

const std::string kOccluderScene = std::string(VKTG_SOURCE_DIR) + "/scenes/occluder_shadow.json";

TEST(CliGrad, SplitTermsWritesTheEdgeTermBesideTheInterior) {
  TempDir dir;
  const fs::path exr = dir / "g.exr";
  CliResult r = runVktg({"grad", kOccluderScene, "--param", "occluder_x", "--resolution", "8x8", "--spp", "4",
                         "--spp-edge", "64", "--split-terms", "--explain", "--out", exr.string()},
                        {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_NE(r.out.find("edge pass: parameters move geometry"), std::string::npos) << r.describe();
  for (const char* name : {"g.exr", "g.interior.exr", "g.edge.exr"}) EXPECT_TRUE(fs::is_regular_file(dir / name)) << name;
  EXPECT_FALSE(fs::exists(dir / "g.pathlength.exr")) << "a gaussian gate has no jumps";
  // The edge image is not empty (the square's silhouette is in view) and finite; the total is the
  // sum of the terms.
  ImageSet total = readExr(exr), interior = readExr(dir / "g.interior.exr"), edge = readExr(dir / "g.edge.exr");
  double edgeMagnitude = 0;
  for (size_t i = 0; i < edge.layers[0].pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(edge.layers[0].pixels[i]));
    edgeMagnitude += std::abs(edge.layers[0].pixels[i]);
    EXPECT_NEAR(total.layers[0].pixels[i], interior.layers[0].pixels[i] + edge.layers[0].pixels[i],
                1e-6 * (1 + std::abs(total.layers[0].pixels[i])));
  }
  EXPECT_GT(edgeMagnitude, 0.0);
}

TEST(CliGrad, SplitTermsWithNpyWritesEachTermsArray) {
  TempDir dir;
  CliResult r = runVktg({"grad", kOccluderScene, "--param", "occluder_x", "--resolution", "4x4", "--spp", "2",
                         "--spp-edge", "8", "--split-terms", "--npy", "--quiet", "--out", (dir / "g.exr").string()},
                        {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  // (H, W, parameters x layers) float32: a 128-byte header and 4 x 4 x 1 values.
  for (const char* name : {"g.npy", "g.interior.npy", "g.edge.npy"})
    EXPECT_EQ(fs::file_size(dir / name), 128u + 16u * 4u) << name;
  EXPECT_FALSE(fs::exists(dir / "g.pathlength.npy")) << "a gaussian gate has no jumps";
}

// Without a scene file, the built-in default scene and its parameters (scenes/cornell_box.json's).
TEST(CliGrad, DifferentiatesTheDefaultScene) {
  TempDir dir;
  CliResult r = runVktg({"grad", "--param", "short_box_x,left_albedo", "--resolution", "4x4", "--spp", "2", "--npy",
                         "--quiet", "--out", (dir / "d.exr").string()},
                        {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_EQ(fs::file_size(dir / "d.npy"), 128u + 16u * 4u * 2u);  // 4 x 4, two parameters, one box-gate layer
}

TEST(CliGrad, ExplainSaysWhyThereIsNoEdgePass) {
  TempDir dir;
  CliResult r = runVktg({"grad", kOccluderScene, "--param", "floor_albedo", "--resolution", "4x4", "--spp", "2",
                         "--explain", "--quiet", "--out", (dir / "a.exr").string()},
                        {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_NE(r.out.find("no edge pass: no selected parameter moves geometry"), std::string::npos) << r.describe();
}

TEST(CliGrad, ExplainNamesAContactBetweenAMovingShapeAndAnother) {
  TempDir dir;
  const std::string resting = std::string(VKTG_SOURCE_DIR) + "/tests/data/contact/box_resting.json";
  const std::string raised = std::string(VKTG_SOURCE_DIR) + "/tests/data/contact/box_raised.json";
  CliResult r = runVktg({"grad", resting, "--param", "box_x", "--resolution", "4x4", "--spp", "2", "--explain",
                         "--quiet", "--out", (dir / "a.exr").string()},
                        {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_NE(r.out.find("warning: contact: 5 edges of 'box' lie on 'floor'"), std::string::npos) << r.describe();
  r = runVktg({"grad", raised, "--param", "box_x", "--resolution", "4x4", "--spp", "2", "--explain", "--quiet",
               "--out", (dir / "b.exr").string()},
              {.cwd = dir.path()});
  ASSERT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_EQ(r.out.find("contact"), std::string::npos) << r.describe();
}

TEST(CliGrad, UnknownTermIsAUsageError) {
  TempDir dir;
  CliResult r = runVktg({"grad", kOccluderScene, "--param", "occluder_x", "--terms", "interior,edges", "--out",
                         (dir / "a.exr").string()},
                        {.cwd = dir.path()});
  EXPECT_TRUE(r.exited && r.exitCode != 0) << r.describe();
  EXPECT_NE(r.err.find("--terms: unknown term 'edges' (interior, edge, pathlength)"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir / "a.exr"));
}

}  // namespace
}  // namespace vktg::test
