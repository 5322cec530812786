// The public C++ API (vktg/vktg.h), linked as a user links it: libvktg and its headers only. Its
// renders and derivative images are the command line's bit for bit; the adjoint pass agrees with
// the forward derivatives weighted by the same d loss / d I within their statistical error; bad
// input is a vktg::Error naming what is wrong; and the validation layer stays silent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <vktg/vktg.h>

#include "support/test_environment.h"

namespace {

namespace fs = std::filesystem;
const fs::path kScene = fs::path(VKTG_SOURCE_DIR) / "scenes" / "occluder_shadow.json";

// A device as the other tests choose it (VKTG_TEST_DEVICE, lavapipe by default), validation on.
vktg::DeviceOptions testDevice() {
  vktg::test::applyTestEnvironment();
  vktg::DeviceOptions o;
  if (const char* device = std::getenv("VKTG_DEVICE")) o.device = device;
  const char* validation = std::getenv("VKTG_VALIDATION");
  o.validation = !validation || std::string(validation) != "0";
  return o;
}

struct TempDir {
  TempDir() : path(fs::temp_directory_path() / ("vktg_api_" + std::to_string(::getpid()) + "_" + std::to_string(rand()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

// The float32 data of a .npy file as `vktg --npy` writes it (little-endian, C order).
std::vector<float> readNpy(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GT(bytes.size(), 10u) << file;
  if (bytes.size() <= 10) return {};
  uint16_t headerBytes = 0;
  std::memcpy(&headerBytes, bytes.data() + 8, 2);
  const size_t first = 10 + headerBytes;
  std::vector<float> data((bytes.size() - first) / sizeof(float));
  std::memcpy(data.data(), bytes.data() + first, data.size() * sizeof(float));
  return data;
}

// An image set's pixels in the .npy order: (height, width, layers).
std::vector<float> npyOrder(const std::vector<vktg::ImageSet>& images) {
  std::vector<float> out;
  if (images.empty()) return out;
  const uint32_t w = images.front().width, h = images.front().height;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (const vktg::ImageSet& image : images)
        for (const vktg::ImageLayer& layer : image.layers) out.push_back(layer.pixels[size_t(y) * w + x]);
  return out;
}

void runCli(const std::string& arguments) {
  const std::string command = std::string(VKTG_BINARY) + " " + arguments + " --quiet";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
}

vktg::GradRequest smallRequest() {
  vktg::GradRequest r;
  r.spp = 16;
  r.resolution = std::pair{16u, 16u};
  return r;
}

TEST(ApiRender, ImagesAreTheCommandLinesBitForBit) {
  vktg::Context context(testDevice());
  TempDir dir;
  runCli("render " + kScene.string() + " --spp 16 --resolution 16x16 --npy --out " + (dir.path / "r.exr").string());
  const vktg::Rendered r = vktg::render(context, vktg::Model::load(kScene), smallRequest());
  ASSERT_EQ(r.images.size(), 1u);
  EXPECT_EQ(r.nonFinite, 0u);
  const std::vector<float> cli = readNpy(dir.path / "r.npy"), api = npyOrder(r.images);
  ASSERT_EQ(cli.size(), api.size());
  EXPECT_EQ(std::memcmp(cli.data(), api.data(), cli.size() * sizeof(float)), 0) << "the library's image differs from vktg render's";
  EXPECT_EQ(context.validationMessages(), 0u);
}

TEST(ApiDerivatives, InteriorTermIsTheCommandLinesBitForBit) {
  vktg::Context context(testDevice());
  TempDir dir;
  runCli("grad " + kScene.string() + " --param occluder_x,floor_albedo --terms interior --spp 16 --resolution 16x16 --npy --out " +
         (dir.path / "g.exr").string());
  vktg::GradRequest request = smallRequest();
  request.edge = request.pathLength = false;
  const vktg::Derivatives d = vktg::derivatives(context, vktg::Model::load(kScene), {"occluder_x", "floor_albedo"}, request);
  ASSERT_EQ(d.total.size(), 2u);
  ASSERT_EQ(d.interior.size(), 2u);
  EXPECT_TRUE(d.edge.empty() && d.pathLength.empty());
  const std::vector<float> cli = readNpy(dir.path / "g.npy"), api = npyOrder(d.total);
  ASSERT_EQ(cli.size(), api.size());
  EXPECT_EQ(std::memcmp(cli.data(), api.data(), cli.size() * sizeof(float)), 0) << "the library's derivatives differ from vktg grad's";
  EXPECT_EQ(context.validationMessages(), 0u);
}

// Σ_pixels w · dI/dθ from the forward lanes (one render, its variance from the pixels' variances)
// against the adjoint pass given w, over independent seeds (its error from their scatter).
TEST(ApiBackward, EqualsTheForwardDerivativesWeightedByTheAdjointImage) {
  vktg::Context context(testDevice());
  const vktg::Model model = vktg::Model::load(kScene);
  const std::vector<std::string> parameters = {"occluder_x", "floor_albedo"};
  vktg::GradRequest request = smallRequest();
  request.spp = 64;
  request.seed = 1;
  const vktg::Derivatives forward = vktg::derivatives(context, model, parameters, request);
  vktg::ImageSet weights = forward.image;
  for (vktg::ImageLayer& layer : weights.layers)
    for (size_t i = 0; i < layer.pixels.size(); ++i) layer.pixels[i] = 1.0f + float(i % weights.width) / float(weights.width);
  constexpr int kSeeds = 8;
  std::vector<std::vector<double>> backward;
  for (int s = 0; s < kSeeds; ++s) {
    request.seed = 100 + s;
    backward.push_back(vktg::renderBackward(context, model, parameters, {weights}, request));
    ASSERT_EQ(backward.back().size(), parameters.size());
  }
  for (size_t k = 0; k < parameters.size(); ++k) {
    double f = 0, fVariance = 0;
    const std::vector<float>& w = weights.layers.front().pixels;
    for (size_t i = 0; i < w.size(); ++i) {
      f += double(w[i]) * forward.total[k].layers.front().pixels[i];
      fVariance += double(w[i]) * w[i] * forward.totalVariance[k].layers.front().pixels[i];
    }
    double mean = 0, spread = 0;
    for (const std::vector<double>& b : backward) mean += b[k] / kSeeds;
    for (const std::vector<double>& b : backward) spread += (b[k] - mean) * (b[k] - mean) / (kSeeds - 1);
    const double se = std::sqrt(fVariance + spread / kSeeds);
    EXPECT_GT(se, 0.0) << parameters[k];
    EXPECT_LT(std::abs(mean - f), 4 * se) << parameters[k] << ": backward " << mean << ", forward " << f << " (s.e. " << se << ")";
  }
  EXPECT_EQ(context.validationMessages(), 0u);
}

TEST(ApiModel, ValuesMoveTheSceneAndAreChecked) {
  vktg::Model model = vktg::Model::load(kScene);
  const std::vector<std::string> names = model.parameterNames();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(model.select("occluder_*").size(), 3u);
  EXPECT_EQ(model.value("occluder_x"), 0.0);
  model.setValue("occluder_x", 0.25);
  EXPECT_EQ(model.values({"occluder_x", "floor_albedo"}), (std::vector<double>{0.25, 0.0}));
  // The occluder's vertices moved by 0.25 along the parameter's axis, the rest did not.
  const vktg::Scene written = model.scene(), moved = model.current();
  const vktg::Parameter& p = written.parameters[0];
  ASSERT_EQ(p.name, "occluder_x");
  for (size_t s = 0; s < written.shapes.size(); ++s) {
    const glm::vec3 d = moved.shapes[s].positions.front() - written.shapes[s].positions.front();
    const glm::vec3 expected = written.shapes[s].name == p.target ? 0.25f * p.axis : glm::vec3(0.0f);
    EXPECT_NEAR(glm::length(d - expected), 0.0f, 1e-6f) << written.shapes[s].name;
  }
  EXPECT_THROW(model.setValue("occluder_x", std::nan("")), vktg::Error);
  EXPECT_THROW(model.setValues({"occluder_x"}, {1.0, 2.0}), vktg::Error);
}

// Each error names what is wrong as the command line names it.
void expectError(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one naming '" << needle << "'";
  } catch (const vktg::Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(ApiErrors, BadInputNamesTheFileFieldAndProblem) {
  vktg::Context context(testDevice());
  const vktg::Model model = vktg::Model::load(kScene);
  expectError([] { vktg::Model::load("no/such/scene.json"); }, "no/such/scene.json");
  expectError([] { vktg::Model::parse("{\"shapes\": 3}", "inline.json"); }, "inline.json");
  expectError([&] { vktg::derivatives(context, model, {"occluder_q"}, smallRequest()); }, "occluder_q");
  expectError([&] { model.value("nope"); }, "nope");
  vktg::ImageSet wrong;
  wrong.width = wrong.height = 3;
  wrong.layers.push_back({"L", std::vector<float>(9, 1.0f)});
  expectError([&] { vktg::renderBackward(context, model, {"occluder_x"}, {wrong}, smallRequest()); }, "adjoints[0]");
  expectError([&] { vktg::renderBackward(context, model, {"occluder_x"}, {}, smallRequest()); }, "adjoints");
  vktg::RenderRequest zeroSpp;
  zeroSpp.spp = 0;
  expectError([&] { vktg::render(context, model, zeroSpp); }, "spp");
  expectError([&] {
        vktg::RenderRequest badGate;
        badGate.gate = vktg::parseGateSpec("box:2,1", "gate");
        vktg::render(context, model, badGate);
      }, "gate");
  EXPECT_EQ(context.validationMessages(), 0u);
}

}  // namespace
