// `vktg render` of a JSON scene whose shape is an OBJ or PLY mesh file: the same prism
// (tests/data/meshes) as OBJ and as binary PLY, itself the emitter, seen from +z. Its top face
// points at the camera, so the centre of the image sees emission 1 and the corners see nothing;
// the two files hold the same mesh and must render the same image.
#include <gtest/gtest.h>

#include "support/cli_runner.h"
#include "vktg/image_io.h"

namespace vktg::test {
namespace {

namespace fs = std::filesystem;
const fs::path kMeshes = fs::path(VKTG_TEST_DATA) / "meshes";

ImageSet renderPrism(const TempDir& dir, const std::string& file) {
  fs::copy_file(kMeshes / file, dir / file, fs::copy_options::overwrite_existing);
  writeJsonFile(dir / "scene.json",
                {{"version", 1},
                 {"camera", {{"type", "perspective"}, {"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"resolution", {16, 16}}}},
                 {"shapes", {{{"name", "prism"}, {"type", "mesh"}, {"file", file}, {"emission", 1}}}},
                 {"render", {{"spp", 2}, {"max_depth", 1}}}});
  const fs::path exr = dir / (file + ".exr");
  runVktgOk({"render", (dir / "scene.json").string(), "--quiet", "--out", exr.string()}, dir);
  return readExr(exr);
}

TEST(CliMeshFiles, ObjAndPlyMeshesRenderTheSameImage) {
  TempDir dir;
  const ImageSet obj = renderPrism(dir, "prism.obj");
  const ImageSet ply = renderPrism(dir, "prism_le.ply");
  ASSERT_EQ(obj.layers.size(), 1u);
  ASSERT_EQ(obj.width, 16u);
  const std::vector<float>& pixels = obj.layers[0].pixels;
  EXPECT_GT(pixels[8 * 16 + 8], 0.5f) << "the centre sees the prism's top face";
  EXPECT_EQ(pixels[0], 0.0f) << "a corner sees past the prism";
  EXPECT_EQ(pixels, ply.layers[0].pixels);
}

}  // namespace
}  // namespace vktg::test
