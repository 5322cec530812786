#include "bench/embree_trace.h"

#if VKTG_HAVE_EMBREE
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <thread>

#include "bench/bench_common.h"
#include "vktg/error.h"
#endif

namespace vktg {

#if VKTG_HAVE_EMBREE
namespace {

// Device and scene, released together.
class EmbreeScene {
 public:
  explicit EmbreeScene(const PreparedScene& prepared) {
    m_device = rtcNewDevice(nullptr);
    if (!m_device) throw Error("embree: cannot create a device");
    m_scene = rtcNewScene(m_device);
    RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
    const size_t count = prepared.triangles.size();
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    for (size_t i = 0; i < count; ++i) {
      const gpu::GpuTriangle& t = prepared.triangles[i];
      const glm::vec4 corners[3] = {t.p0, t.p1, t.p2};
      for (int c = 0; c < 3; ++c) {
        for (int a = 0; a < 3; ++a) vertices[9 * i + 3 * c + a] = corners[c][a];
        indices[3 * i + c] = unsigned(3 * i + c);
      }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(m_scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(m_scene);
  }
  ~EmbreeScene() {
    rtcReleaseScene(m_scene);
    rtcReleaseDevice(m_device);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene scene() const { return m_scene; }

 private:
  RTCDevice m_device = nullptr;
  RTCScene m_scene = nullptr;
};

RTCRay embreeRay(const TraceRay& r) {
  RTCRay ray{};
  ray.org_x = r.origin.x, ray.org_y = r.origin.y, ray.org_z = r.origin.z;
  ray.dir_x = r.direction.x, ray.dir_y = r.direction.y, ray.dir_z = r.direction.z;
  ray.tnear = r.tMin;
  ray.tfar = r.tMax;
  ray.mask = ~0u;
  return ray;
}

// Rays [begin, end) once; writes whether each hit.
void traceRange(RTCScene scene, const std::vector<TraceRay>& rays, bool anyHit, size_t begin, size_t end,
                std::vector<char>& hit) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = begin; i < end; ++i) {
    if (anyHit) {
      RTCRay ray = embreeRay(rays[i]);
      rtcOccluded1(scene, &context, &ray);
      hit[i] = ray.tfar < 0;  // Embree sets tfar to -inf on occlusion
    } else {
      RTCRayHit rayHit{};
      rayHit.ray = embreeRay(rays[i]);
      rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rayHit);
      hit[i] = rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  }
}

// All rays once, split over every hardware thread; returns the seconds taken.
double traceAll(RTCScene scene, const std::vector<TraceRay>& rays, bool anyHit, std::vector<char>& hit) {
  const size_t threads = std::max(1u, std::thread::hardware_concurrency());
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> workers;
  for (size_t k = 0; k < threads; ++k)
    workers.emplace_back(traceRange, scene, std::cref(rays), anyHit, rays.size() * k / threads,
                         rays.size() * (k + 1) / threads, std::ref(hit));
  for (std::thread& w : workers) w.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::string embreeVersion() { return std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." + std::to_string(RTC_VERSION_PATCH); }

std::optional<EmbreeTiming> embreeTrace(const PreparedScene& prepared, const std::vector<TraceRay>& rays, bool anyHit,
                                        double budgetSeconds, uint32_t runs) {
  EmbreeScene embree(prepared);
  std::vector<char> hit(rays.size(), 0);
  const double once = traceAll(embree.scene(), rays, anyHit, hit);  // also warms the caches
  const uint32_t repeats = uint32_t(std::clamp(budgetSeconds / std::max(once, 1e-6), 1.0, 1000.0));
  std::vector<double> rates;
  for (uint32_t run = 0; run < runs; ++run) {
    double seconds = 0;
    for (uint32_t k = 0; k < repeats; ++k) seconds += traceAll(embree.scene(), rays, anyHit, hit);
    rates.push_back(double(rays.size()) * repeats / seconds);
  }
  EmbreeTiming timing;
  timing.raysPerSecond = median(rates);
  timing.hits.assign(hit.begin(), hit.end());
  return timing;
}

#else

std::string embreeVersion() { return ""; }

std::optional<EmbreeTiming> embreeTrace(const PreparedScene&, const std::vector<TraceRay>&, bool, double, uint32_t) {
  return std::nullopt;
}

#endif

}  // namespace vktg
