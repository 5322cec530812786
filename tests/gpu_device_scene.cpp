// The device-resident scene moving in place (DeviceScene::update): the device's moved vertices are
// the host model's (ParameterModel, double precision) to float rounding; the refit BVH is the
// host's refit of the same tree; a render of the moved scene is a render of the scene built afresh
// at θ (same random numbers: only float rounding of the positions differs, so the images agree to
// far within their noise); a tree that motion degraded is rebuilt, and the rebuild is reproducible
// from the θ it was built at.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>

#include "render/device_scene.h"
#include "support/gpu_context.h"
#include "support/render_test.h"
#include "vktg/bvh.h"
#include "vktg/silhouette_edges.h"

namespace vktg::test {
namespace {

Scene movingScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.6, 2.4], "look_at": [0, 0, 0], "fov_y": 45, "resolution": [24, 24]},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.6}, "white": {"type": "diffuse", "albedo": 0.8}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [5, 5], "size": [2, 2], "material": "ground",
       "heights": [0, 0, 0, 0, 0, 0, 0.1, 0.2, 0.1, 0, 0, 0.2, 0.3, 0.2, 0, 0, 0.1, 0.2, 0.1, 0, 0, 0, 0, 0, 0]},
      {"name": "box", "type": "cube", "material": "white", "transform": {"translate": [0.3, 0.4, -0.2], "scale": 0.15}},
      {"name": "lamp", "type": "rectangle", "emission": 6, "transform": {"translate": [0, 1.5, 0], "rotate": [90, 0, 0], "scale": 0.4}}
    ],
    "parameters": [
      {"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"},
      {"name": "slide", "type": "translate", "shape": "box", "axis": [1, 0, 0]},
      {"name": "spin", "type": "rotate", "shape": "box", "axis": [0, 1, 0]},
      {"name": "glow", "type": "emission", "shape": "lamp"},
      {"name": "grey", "type": "albedo", "material": "ground"}
    ],
    "render": {"spp": 64, "max_depth": 3, "seed": 4}
  })", "moving.json", ".");
}

std::vector<uint32_t> allParameters(const Scene& scene) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < scene.parameters.size(); ++i) out.push_back(i);
  return out;
}

std::vector<double> someTheta(const ParameterModel& model) {
  std::vector<double> theta(model.size(), 0.0);
  for (size_t k = 0; k < theta.size(); ++k) {
    const std::string& name = model.parameter(k).name;
    if (name[0] == 'h') theta[k] = 0.05 * std::sin(3.0 * double(k));
  }
  theta[findParameter(model.baseScene(), "slide")] = -0.2;
  theta[findParameter(model.baseScene(), "spin")] = 0.6;
  theta[findParameter(model.baseScene(), "glow")] = 2.0;
  theta[findParameter(model.baseScene(), "grey")] = -0.2;
  return theta;
}

template <class T>
std::vector<T> download(const Buffer& buffer, size_t count) {
  std::vector<T> out(count);
  buffer.download(testContext(), out.data(), count * sizeof(T));
  return out;
}

std::vector<gpu::GpuBvhNode> downloadNodes(const ChunkedBuffer& chunks, size_t count) {
  std::vector<gpu::GpuBvhNode> out(count);
  const size_t perChunk = size_t(1) << chunks.shift;
  for (size_t c = 0; c < chunks.chunks.size(); ++c) {
    size_t first = c * perChunk, n = std::min(perChunk, count - std::min(count, first));
    if (n > 0) chunks.chunks[c].download(testContext(), out.data() + first, n * sizeof(gpu::GpuBvhNode));
  }
  return out;
}

TEST(DeviceScene, MovedVerticesAreTheModels) {
  const Scene scene = movingScene();
  ParameterModel model(scene, allParameters(scene));
  const std::vector<double> zero(model.size(), 0.0), theta = someTheta(model);
  DeviceScene device(testContext(), model, zero, zero);
  device.update(theta, false);
  const std::vector<glm::vec4> moved = download<glm::vec4>(device.gpu().vertices, device.prepared().vertices.size());
  size_t v = 0;
  double worst = 0;
  for (uint32_t s = 0; s < scene.shapes.size(); ++s)
    for (const glm::dvec3& expected : model.shapePositions(theta, s)) {
      // Float rounding of a rotation and a sum of a few terms: a few ulps of coordinates below 2.
      const double error = glm::length(glm::dvec3(moved[v++]) - expected);
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-6) << "vertex " << v - 1;
    }
  std::printf("  largest device - host vertex distance %.3g\n", worst);
  // Scalars follow θ on the host side.
  EXPECT_FLOAT_EQ(device.scene().materials[0].albedo, 0.4f);
  EXPECT_FLOAT_EQ(device.scene().shapes[2].emission, 8.0f);
}

TEST(DeviceScene, RefitIsTheHostRefitOfTheSameTree) {
  const Scene scene = movingScene();
  ParameterModel model(scene, allParameters(scene));
  const std::vector<double> zero(model.size(), 0.0), theta = someTheta(model);
  DeviceScene device(testContext(), model, theta, zero);  // built at 0, moved to θ
  Bvh host = device.prepared().bvh;
  const Scene moved = model.sceneAt(theta);
  std::vector<glm::vec3> vertices;
  for (const Shape& s : moved.shapes) vertices.insert(vertices.end(), s.positions.begin(), s.positions.end());
  std::vector<BvhTriangle> soup;
  for (const glm::uvec4& t : device.prepared().triangleVerts) soup.push_back({vertices[t.x], vertices[t.y], vertices[t.z]});
  refitBvh(host, soup);
  const std::vector<gpu::GpuBvhNode> nodes = downloadNodes(device.gpu().bvhNodes, host.nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const gpu::GpuBvhNode &a = nodes[i], &b = host.nodes[i];
    EXPECT_EQ(std::bit_cast<uint32_t>(a.rightMinCount.w), std::bit_cast<uint32_t>(b.rightMinCount.w)) << "node " << i;
    if (std::bit_cast<uint32_t>(a.rightMinCount.w) > 0) continue;  // a leaf's boxes are unused
    for (auto [x, y] : {std::pair{a.leftMinLeftIndex, b.leftMinLeftIndex}, {a.leftMaxRightIndex, b.leftMaxRightIndex},
                        {a.rightMinCount, b.rightMinCount}, {a.rightMaxFirst, b.rightMaxFirst}})
      EXPECT_LT(glm::length(glm::vec3(x) - glm::vec3(y)), 2e-6f) << "node " << i;
  }
  // The 4-wide tree (CPU devices) follows: every child box is the device's binary box it came from.
  if (!device.gpu().wideBvh()) return;
  const std::vector<gpu::GpuWideBvhNode> built = collapseBvh(device.prepared().bvh);
  const std::vector<gpu::GpuWideBvhNode> wide = download<gpu::GpuWideBvhNode>(device.gpu().wideBvhNodes, built.size());
  size_t changed = 0;
  for (size_t i = 0; i < wide.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      const uint32_t source = wide[i].source[k];
      if (source == gpu::kWideBvhEmpty) continue;
      const gpu::GpuBvhNode& n = nodes[source / 2];
      const glm::vec3 lo(source % 2 ? n.rightMinCount : n.leftMinLeftIndex), hi(source % 2 ? n.rightMaxFirst : n.leftMaxRightIndex);
      EXPECT_EQ(glm::vec3(wide[i].loX[k], wide[i].loY[k], wide[i].loZ[k]), lo) << "wide node " << i << " slot " << k;
      EXPECT_EQ(glm::vec3(wide[i].hiX[k], wide[i].hiY[k], wide[i].hiZ[k]), hi) << "wide node " << i << " slot " << k;
      changed += wide[i].loY[k] != built[i].loY[k] || wide[i].hiY[k] != built[i].hiY[k];
    }
  EXPECT_GT(changed, 0u) << "the motion should have changed some wide boxes";
}

// An update rebuilds the light table from the emitting triangles alone: the table a pass over every
// triangle gives, with the areas the emitters' moved vertices span. The heightfield emits here, so
// its heights change its triangles' areas and hence the light selection.
TEST(DeviceScene, LightTableOfADeformedEmitterIsTheFullScans) {
  Scene scene = movingScene();
  scene.shapes[0].emission = 0.5f;
  ParameterModel model(scene, allParameters(scene));
  const std::vector<double> zero(model.size(), 0.0), theta = someTheta(model);
  DeviceScene device(testContext(), model, zero, zero);
  device.update(theta, false);
  const PreparedScene& updated = device.prepared();
  const std::vector<glm::dvec3> ground = model.shapePositions(theta, 0);  // shape 0: vertices from 0
  size_t groundTriangles = 0;
  for (size_t i = 0; i < updated.triangles.size(); ++i) {
    const glm::uvec4& ids = updated.triangleVerts[i];
    if (ids.w != 0) continue;
    ++groundTriangles;
    const glm::dvec3 a = ground[ids.x], b = ground[ids.y], c = ground[ids.z];
    EXPECT_NEAR(updated.triangles[i].p2.w, 0.5 * glm::length(glm::cross(b - a, c - a)), 1e-6) << "triangle " << i;
  }
  EXPECT_EQ(groundTriangles, 32u);
  PreparedScene full = updated;
  prepareLights(full, device.scene());
  ASSERT_EQ(full.lights.size(), updated.lights.size());
  EXPECT_EQ(updated.lights.size(), 32u + 2u) << "the ground's triangles and the lamp's two";
  for (size_t i = 0; i < full.lights.size(); ++i)
    EXPECT_EQ(std::memcmp(&full.lights[i], &updated.lights[i], sizeof(gpu::GpuLight)), 0) << "light " << i;
  EXPECT_EQ(full.totalLightPower, updated.totalLightPower);
}

// Same seed, same paths: the moved scene renders as the scene built at θ does.
void expectRendersLikeAFreshScene(DeviceScene& device, const Scene& fresh) {
  RenderOptions options;
  options.nee = NeeMode::Standard;
  RenderResult a = testRenderer().render(device, RenderSetup::of(fresh), options);
  RenderResult b = testRenderer().render(fresh, options);
  ImageMean ma = imageMean(a.mean.layers[0].pixels, a.variance.layers[0].pixels);
  ImageMean mb = imageMean(b.mean.layers[0].pixels, b.variance.layers[0].pixels);
  std::printf("  image means: moved %.7g, fresh %.7g (standard error %.2g)\n", ma.mean, mb.mean, ma.standardError);
  EXPECT_GT(ma.mean, 0.0);
  // The two estimates share their samples: they differ by float rounding of positions only, far
  // below their standard error; a lost triangle or a stale light table would not.
  EXPECT_LT(std::abs(ma.mean - mb.mean), 0.02 * ma.standardError);
  size_t differing = 0;
  for (size_t i = 0; i < a.mean.layers[0].pixels.size(); ++i) {
    float x = a.mean.layers[0].pixels[i], y = b.mean.layers[0].pixels[i];
    if (std::abs(x - y) > 1e-3f * std::max(std::abs(y), 1e-3f)) ++differing;
  }
  EXPECT_LE(differing, a.mean.layers[0].pixels.size() / 100) << "pixels that differ beyond rounding";
}

TEST(DeviceScene, MovedSceneRendersLikeAFreshOne) {
  const Scene scene = movingScene();
  ParameterModel model(scene, allParameters(scene));
  const std::vector<double> zero(model.size(), 0.0), theta = someTheta(model);
  DeviceScene device(testContext(), model, zero, zero);
  device.update(theta, false);
  expectRendersLikeAFreshScene(device, model.sceneAt(theta));
}

// An n x n heightfield of bumps whose every height is a parameter, as an optimisation moves it.
Scene bumpyField(uint32_t n) {
  std::string heights;
  for (uint32_t i = 0; i < n * n; ++i) heights += (i ? ", " : "") + std::to_string(0.1 * std::sin(0.37 * double(i)));
  const std::string size = std::to_string(n);
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.6, 2.4], "look_at": [0, 0, 0], "resolution": [8, 8]},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.6}},
    "shapes": [
      {"name": "ground", "type": "heightfield", "resolution": [)" + size + ", " + size + R"(], "size": [2, 2],
       "material": "ground", "heights": [)" + heights + R"(]},
      {"name": "lamp", "type": "rectangle", "emission": 6, "transform": {"translate": [0, 1.5, 0], "rotate": [90, 0, 0], "scale": 0.4}}
    ],
    "parameters": [{"type": "heightfield_heights", "shape": "ground", "name_prefix": "h"}]
  })", "bumpy.json", ".");
}

// The quality check sums the refit tree's SAH cost on the device (bvh_sah_cost: partial sums over
// runs of 64 nodes, added on the host): the host's sum over the same refit tree in double
// (refitSahCost) up to float rounding, for a tree of a partial sum or two and one of a hundred, as
// built and moved. A lost partial sum, a child's cost or box taken wrongly, moves it by far more.
TEST(DeviceScene, QualityCheckSumsTheRefitTreesSahCost) {
  for (uint32_t n : {5u, 60u}) {
    SCOPED_TRACE("heightfield " + std::to_string(n) + " x " + std::to_string(n));
    const Scene scene = bumpyField(n);
    ParameterModel model(scene, allParameters(scene));
    const std::vector<double> zero(model.size(), 0.0);
    std::vector<double> theta(model.size());
    for (size_t k = 0; k < theta.size(); ++k) theta[k] = 0.3 * std::sin(1.7 * double(k));
    DeviceScene device(testContext(), model, zero, zero);
    // The tree as built and its leaf order (a check that finds it degraded rebuilds it).
    const Bvh built = device.prepared().bvh;
    const std::vector<glm::uvec4> leafOrder = device.prepared().triangleVerts;
    ASSERT_GT(built.nodes.size(), n > 5 ? 10u * gpu::kWorkgroupSize : 1u);
    device.update(zero, true);
    EXPECT_NEAR(device.lastSahRatio(), 1.0, 1e-5);
    device.update(theta, true);
    const Scene moved = model.sceneAt(theta);
    std::vector<glm::vec3> vertices;
    for (const Shape& shape : moved.shapes) vertices.insert(vertices.end(), shape.positions.begin(), shape.positions.end());
    std::vector<BvhTriangle> soup;
    for (const glm::uvec4& t : leafOrder) soup.push_back({vertices[t.x], vertices[t.y], vertices[t.z]});
    const double hostRatio = refitSahCost(built, soup) / bvhSahCost(built);
    std::printf("  refit / built SAH cost: device %.7f, host %.7f\n", device.lastSahRatio(), hostRatio);
    EXPECT_GT(hostRatio, 1.01);  // the motion changed the tree's cost
    EXPECT_NEAR(device.lastSahRatio(), hostRatio, 1e-5 * hostRatio);
  }
}

TEST(DeviceScene, DegradedTreeIsRebuiltReproducibly) {
  const Scene scene = movingScene();
  ParameterModel model(scene, allParameters(scene));
  const std::vector<double> zero(model.size(), 0.0);
  std::vector<double> theta = someTheta(model);
  // Every other height far up: the refit boxes of the flat ground balloon.
  for (size_t k = 0; k < 25; k += 2) theta[findParameter(scene, "h" + std::to_string(k))] = 1.5;
  DeviceScene device(testContext(), model, zero, zero);
  device.edges(model.movingVertices(), model.deformingVertices());
  const std::vector<glm::uvec4> leafOrder = device.prepared().triangleVerts;
  device.update(theta, true);
  std::printf("  SAH cost of the refit tree / when built: %.3f, rebuilds %u\n", device.lastSahRatio(), device.rebuilds());
  EXPECT_GT(device.lastSahRatio(), kBvhRebuildRatio);
  EXPECT_EQ(device.rebuilds(), 1u);
  // The edge list is made again with the tree: its faces name their triangles in the new leaf order.
  EXPECT_NE(device.prepared().triangleVerts, leafOrder);
  const EdgeList edges = edgeList(device.prepared(), model.movingVertices(), model.deformingVertices());
  EXPECT_EQ(download<glm::uvec4>(device.edgeFaces(), edges.faces.size()), edges.faces);
  EXPECT_EQ(std::vector<double>(device.buildTheta().begin(), device.buildTheta().end()), theta);
  expectRendersLikeAFreshScene(device, model.sceneAt(theta));
  // A scene built at the recorded θ holds the same tree (what a resumed run relies on).
  DeviceScene again(testContext(), model, theta, device.buildTheta());
  EXPECT_EQ(again.prepared().bvh.order, device.prepared().bvh.order);
  const std::vector<gpu::GpuBvhNode> a = downloadNodes(device.gpu().bvhNodes, device.prepared().bvh.nodes.size());
  const std::vector<gpu::GpuBvhNode> b = downloadNodes(again.gpu().bvhNodes, again.prepared().bvh.nodes.size());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(gpu::GpuBvhNode)));
}

}  // namespace
}  // namespace vktg::test
