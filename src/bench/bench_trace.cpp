#include "bench/bench_trace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <sstream>
#include <thread>

#include "bench/bench_scenes.h"
#include "bench/embree_trace.h"
#include "render/frame_uniforms.h"
#include "render/pass_pipelines.h"
#include "vktg/bvh.h"
#include "vktg/image_io.h"
#include "vktg/prepared_scene.h"

namespace vktg {
namespace {

glm::vec3 uniformSphere(std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const float z = 1.0f - 2.0f * uniform(rng), phi = 2.0f * std::numbers::pi_v<float> * uniform(rng);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Camera rays through jittered pixel positions, pixel after pixel (coherent, like a render's first
// bounce); a point sensor's rays are cosine-distributed around its normal.
std::vector<TraceRay> primaryRays(const Camera& camera, uint32_t count, std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<TraceRay> rays(count);
  const CameraBasis basis = cameraBasis(camera);
  const uint32_t pixels = camera.width * camera.height;
  for (uint32_t i = 0; i < count; ++i) {
    glm::vec3 direction;
    if (camera.type == CameraType::PointSensor) {
      direction = glm::normalize(camera.normal + uniformSphere(rng));  // cosine-weighted
    } else {
      const uint32_t pixel = i % pixels;
      const float u = (float(pixel % camera.width) + uniform(rng)) / float(camera.width);
      const float v = (float(pixel / camera.width) + uniform(rng)) / float(camera.height);
      direction = glm::normalize(basis.forward + (2.0f * u - 1.0f) * basis.right + (1.0f - 2.0f * v) * basis.up);
    }
    rays[i] = {camera.position, 0.0f, direction, INFINITY};
  }
  return rays;
}

// Rays from uniformly chosen points of uniformly chosen triangles in uniform directions: the
// incoherent rays of later bounces, with the renderer's self-intersection offset as tMin.
std::vector<TraceRay> incoherentRays(const PreparedScene& prepared, uint32_t count, float tMin, std::mt19937& rng) {
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::uniform_int_distribution<size_t> pick(0, prepared.triangles.size() - 1);
  std::vector<TraceRay> rays(count);
  for (TraceRay& ray : rays) {
    const gpu::GpuTriangle& t = prepared.triangles[pick(rng)];
    float a = uniform(rng), b = uniform(rng);
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    ray = {glm::vec3(t.p0) + a * (glm::vec3(t.p1) - glm::vec3(t.p0)) + b * (glm::vec3(t.p2) - glm::vec3(t.p0)), tMin,
           uniformSphere(rng), INFINITY};
  }
  return rays;
}

// The scene on the device and the bench_trace pass over a set of rays.
class GpuTracer {
 public:
  GpuTracer(VulkanContext& context, const Scene& scene, const PreparedScene& prepared, const std::vector<TraceRay>& rays)
      : m_context(context),
        m_scene(context, prepared),
        m_pipelines(context, kShaderRegistry, defaultPipelineCacheFile(context)),
        m_dummy(context, 256, MemoryKind::Device, "bench.dummy"),
        m_rays(context, rays.size() * sizeof(TraceRay), MemoryKind::Device, "bench.rays"),
        m_hits(context, rays.size() * sizeof(gpu::HitRecord), MemoryKind::Device, "bench.hits"),
        m_frame(context, sizeof(gpu::FrameUniforms), MemoryKind::Device, "bench.frame"),
        m_count(uint32_t(rays.size())) {
    static_assert(sizeof(TraceRay) == 8 * sizeof(float), "bench_trace.comp reads 8 floats per ray");
    m_rays.upload(context, rays.data(), rays.size() * sizeof(TraceRay));
    const gpu::FrameUniforms frame = sceneFrameUniforms(scene.camera, scene.render, prepared, m_scene);
    m_frame.upload(context, &frame, sizeof frame);
    BindingTable table;
    table.setScene(m_scene);
    table.set(gpu::kBindingFrame, m_frame);
    table.set(gpu::kBindingPathAccum, m_rays);
    table.set(gpu::kBindingHits, m_hits);
    m_set.emplace(context, m_pipelines, table, m_dummy);
  }

  // Seconds for `repeats` passes over every ray (one submission; the first call also builds the
  // pipeline, so callers warm up first).
  double trace(bool anyHit, uint32_t repeats) {
    SpecValues spec{};
    spec[gpu::kSpecSingleChunk] = m_scene.singleChunk() ? 1u : 0u;
    spec[gpu::kSpecSceneTexels] = m_scene.texels() ? 1u : 0u;
    spec[gpu::kSpecWideBvh] = m_scene.wideBvh() ? 1u : 0u;
    VkPipeline pipeline = m_pipelines.get("bench_trace", spec);
    CommandBuffer cmd(m_context, "bench trace");
    cmd.begin();
    vkCmdBindPipeline(cmd.get(), VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    VkDescriptorSet set = m_set->get();
    vkCmdBindDescriptorSets(cmd.get(), VK_PIPELINE_BIND_POINT_COMPUTE, m_pipelines.layout(), 0, 1, &set, 0, nullptr);
    gpu::PassPush push{glm::uvec4(m_count, anyHit ? 1u : 0u, 0u, 0u)};
    vkCmdPushConstants(cmd.get(), m_pipelines.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    for (uint32_t k = 0; k < repeats; ++k) {
      if (k > 0) computeBarrier(cmd.get());
      vkCmdDispatch(cmd.get(), (m_count + gpu::kWorkgroupSize - 1) / gpu::kWorkgroupSize, 1, 1);
    }
    cmd.end();
    const auto start = std::chrono::steady_clock::now();
    m_context.submitAndWait(cmd.get());
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  bool wideBvh() const { return m_scene.wideBvh(); }

  std::vector<gpu::HitRecord> hits() const {
    std::vector<gpu::HitRecord> out(m_count);
    m_hits.download(m_context, out.data(), out.size() * sizeof(gpu::HitRecord));
    return out;
  }

 private:
  VulkanContext& m_context;
  GpuScene m_scene;
  PassPipelines m_pipelines;
  Buffer m_dummy, m_rays, m_hits, m_frame;
  std::optional<DescriptorSet> m_set;
  uint32_t m_count;
};

// Compares the first rays' device answers with the host traversal (the tests' reference).
// The prepared scene's triangles (leaf order) as the host traversal takes them.
std::vector<BvhTriangle> hostTriangles(const PreparedScene& prepared) {
  std::vector<BvhTriangle> triangles(prepared.triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i)
    triangles[i] = {glm::vec3(prepared.triangles[i].p0), glm::vec3(prepared.triangles[i].p1),
                    glm::vec3(prepared.triangles[i].p2)};
  return triangles;
}

void checkAgainstHost(const PreparedScene& prepared, const std::vector<BvhTriangle>& triangles,
                      const std::vector<TraceRay>& rays, bool anyHit, const std::vector<gpu::HitRecord>& hits,
                      BenchTraceRow& row) {
  row.checked = uint32_t(std::min<size_t>(rays.size(), 4096));
  for (uint32_t i = 0; i < row.checked; ++i) {
    const TraceRay& r = rays[i];
    const float t = hits[i].tuvTriangle.x;
    if (anyHit) {
      row.disagreements += traceAny(prepared.bvh, triangles, r.origin, r.direction, r.tMin, r.tMax) != (t > 0);
      continue;
    }
    const std::optional<RayHit> host = traceClosest(prepared.bvh, triangles, r.origin, r.direction, r.tMin, r.tMax);
    if (host.has_value() != (t >= 0)) row.disagreements++;
    else if (host && std::abs(host->t - t) > 1e-5f * std::max(1.0f, host->t)) row.disagreements++;
  }
}

struct NamedScene {
  std::string name;
  Scene scene;
};

std::vector<NamedScene> scenesToTrace(const BenchTraceOptions& options) {
  std::vector<NamedScene> scenes;
  if (!options.scene.empty()) {
    scenes.push_back({options.scene.filename().string(), loadScene(options.scene, options.defines)});
    return scenes;
  }
  scenes.push_back({"default room", defaultScene()});
  for (uint32_t n : options.sizes)
    scenes.push_back({"room, " + std::to_string(n) + "x" + std::to_string(n) + " heightfield", tessellatedRoom(n, 64)});
  return scenes;
}

}  // namespace

BenchTraceReport benchTrace(VulkanContext& context, const BenchTraceOptions& options) {
  BenchTraceReport report;
  report.device = context.report().name;
  if (options.embree) report.embree = embreeVersion();
  const uint32_t count = std::max<uint32_t>(4096, uint32_t(double(options.rays) * options.scale));
  const double budget = options.secondsPerPoint * options.scale;
  for (const NamedScene& named : scenesToTrace(options)) {
    const PreparedScene prepared = prepareScene(named.scene);
    const float tMin = surfaceOffset(prepared);
    const std::vector<BvhTriangle> triangles = hostTriangles(prepared);
    options.say(named.name + ": " + std::to_string(prepared.triangles.size()) + " triangles");
    std::mt19937 rng(1234);
    for (const char* kind : {"primary", "incoherent"}) {
      const std::vector<TraceRay> rays = std::string(kind) == "primary"
                                             ? primaryRays(named.scene.camera, count, rng)
                                             : incoherentRays(prepared, count, tMin, rng);
      GpuTracer tracer(context, named.scene, prepared, rays);
      for (bool anyHit : {false, true}) {
        BenchTraceRow row;
        row.scene = named.name;
        row.triangles = prepared.triangles.size();
        row.rays = kind;
        row.query = anyHit ? "any" : "closest";
        row.tree = tracer.wideBvh() ? "4-wide" : "binary";
        const double once = tracer.trace(anyHit, 1);  // warm-up: builds the pipeline
        const double perPass = tracer.trace(anyHit, 1);
        const uint32_t repeats = uint32_t(std::clamp(budget / std::max(std::min(once, perPass), 1e-6), 1.0, 10000.0));
        std::vector<double> rates;
        for (uint32_t run = 0; run < options.runs; ++run) rates.push_back(double(count) * repeats / tracer.trace(anyHit, repeats));
        row.raysPerSecond = median(rates);
        const std::vector<gpu::HitRecord> hits = tracer.hits();
        size_t hit = 0;
        for (const gpu::HitRecord& h : hits) hit += anyHit ? h.tuvTriangle.x > 0 : h.tuvTriangle.x >= 0;
        row.hitFraction = double(hit) / double(count);
        checkAgainstHost(prepared, triangles, rays, anyHit, hits, row);
        if (!report.embree.empty()) {
          if (std::optional<EmbreeTiming> embree = embreeTrace(prepared, rays, anyHit, budget, options.runs)) {
            row.embreeRaysPerSecond = embree->raysPerSecond;
            for (size_t i = 0; i < hits.size(); ++i)
              row.embreeDisagreements += embree->hits[i] != (anyHit ? hits[i].tuvTriangle.x > 0 : hits[i].tuvTriangle.x >= 0);
          }
        }
        char line[256];
        std::snprintf(line, sizeof line, "  %-10s %-7s %.3g rays/s (%s BVH), Embree %.3g (hit %.1f%%, %u of %u differ from the host)",
                      kind, row.query.c_str(), row.raysPerSecond, row.tree.c_str(), row.embreeRaysPerSecond, 100.0 * row.hitFraction,
                      row.disagreements, row.checked);
        options.say(line);
        report.rows.push_back(row);
      }
    }
  }
  return report;
}

void writeBenchTraceReport(const BenchTraceReport& report, const BenchTraceOptions& options, const std::string& command) {
  std::ostringstream csv;
  csv << "scene,triangles,rays,query,tree,rays_per_second,embree_rays_per_second,hit_fraction,checked,disagreements,"
         "embree_disagreements\n";
  for (const BenchTraceRow& r : report.rows)
    csv << "\"" << r.scene << "\"," << r.triangles << "," << r.rays << "," << r.query << "," << r.tree << "," << r.raysPerSecond << ","
        << r.embreeRaysPerSecond << "," << r.hitFraction << "," << r.checked << "," << r.disagreements << ","
        << r.embreeDisagreements << "\n";
  std::filesystem::create_directories(options.outDir);
  writeFileAtomic(options.outDir / "bench.csv", csv.str());

  std::ostringstream md;
  md << "Command: `" << command << "`  \nDevice: " << report.device << "  \n"
     << (report.embree.empty() ? std::string("Embree: not built in")
                               : "Embree " + report.embree + " on " + std::to_string(std::thread::hardware_concurrency()) +
                                     " host threads, the same rays")
     << "  \nMedians of " << options.runs << " runs, each tracing its ray set until the time budget.\n\n"
     << "| scene | triangles | rays | query | BVH | vktg Mrays/s | Embree Mrays/s | vktg / Embree | hits |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  char cell[320], embree[64];
  for (const BenchTraceRow& r : report.rows) {
    if (r.embreeRaysPerSecond > 0)
      std::snprintf(embree, sizeof embree, "%.3g | %.3fx", r.embreeRaysPerSecond * 1e-6, r.raysPerSecond / r.embreeRaysPerSecond);
    else
      std::snprintf(embree, sizeof embree, "- | -");
    std::snprintf(cell, sizeof cell, "| %s | %llu | %s | %s | %s | %.3g | %s | %.1f%% |\n", r.scene.c_str(),
                  (unsigned long long)r.triangles, r.rays.c_str(), r.query.c_str(), r.tree.c_str(), r.raysPerSecond * 1e-6, embree,
                  100.0 * r.hitFraction);
    md << cell;
  }
  writeFileAtomic(options.outDir / "table.md", md.str());
}

}  // namespace vktg
