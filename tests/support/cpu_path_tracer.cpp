#include "support/cpu_path_tracer.h"

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "vktg/prepared_scene.h"

namespace vktg::test {
namespace {

using dvec3 = glm::dvec3;

struct Basis {
  dvec3 t, b, n;
};

// Any orthonormal basis with n as third axis.
Basis basisAround(dvec3 n) {
  dvec3 helper = std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  dvec3 t = glm::normalize(glm::cross(helper, n));
  return {t, glm::cross(n, t), n};
}

// Cosine-weighted direction about n (Malley: uniform disk lifted to the hemisphere).
dvec3 cosineDirection(dvec3 n, double u1, double u2) {
  double r = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
  Basis f = basisAround(n);
  return glm::normalize(r * std::cos(phi) * f.t + r * std::sin(phi) * f.b + std::sqrt(std::max(0.0, 1.0 - u1)) * f.n);
}

}  // namespace

CpuRenderResult cpuPathTrace(const Scene& scene, uint32_t spp, uint32_t maxDepth, uint64_t seed,
                             const std::function<double(double)>& gate) {
  for (const Material& m : scene.materials)
    if (m.type != MaterialType::Diffuse) throw std::runtime_error("cpuPathTrace: diffuse materials only");
  if (!scene.pointLights.empty()) throw std::runtime_error("cpuPathTrace: point lights cannot be hit");

  PreparedScene prepared = prepareScene(scene);
  std::vector<BvhTriangle> tris(prepared.triangleVerts.size());
  std::vector<dvec3> normals(tris.size());
  std::vector<uint32_t> shapeOf(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) {
    glm::uvec4 v = prepared.triangleVerts[i];
    tris[i] = {glm::vec3(prepared.vertices[v.x]), glm::vec3(prepared.vertices[v.y]), glm::vec3(prepared.vertices[v.z])};
    dvec3 p0(tris[i].p0), p1(tris[i].p1), p2(tris[i].p2);
    normals[i] = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    shapeOf[i] = v.w;
  }
  // Rays leave a surface after this distance, so they cannot hit the triangle they start on.
  double tEps = 1e-5 * std::max(1.0, double(glm::length(prepared.boundsMax - prepared.boundsMin)));

  const Camera& cam = scene.camera;
  bool point = cam.type == CameraType::PointSensor;
  CpuRenderResult out;
  out.width = point ? 1 : cam.width;
  out.height = point ? 1 : cam.height;
  dvec3 forward, right, up;
  if (point) {
    forward = glm::normalize(dvec3(cam.normal));
  } else {
    forward = glm::normalize(dvec3(cam.lookAt) - dvec3(cam.position));
    right = glm::normalize(glm::cross(forward, dvec3(cam.up)));
    up = glm::cross(right, forward);
    double tanHalf = std::tan(cam.fovY * std::numbers::pi / 360.0);
    right *= tanHalf * double(cam.width) / double(cam.height);
    up *= tanHalf;
  }

  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 12345);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  size_t pixels = size_t(out.width) * out.height;
  out.mean.assign(pixels, 0.0);
  out.variance.assign(pixels, 0.0);
  for (size_t pixel = 0; pixel < pixels; ++pixel) {
    double sum = 0, sumSq = 0;
    for (uint32_t s = 0; s < spp; ++s) {
      dvec3 origin(cam.position), dir;
      double throughput = 1.0;
      if (point) {
        // Importance cos / pdf(cos / pi) = pi: the sensor measures the integral of L cos.
        dir = cosineDirection(forward, uniform(rng), uniform(rng));
        throughput = std::numbers::pi;
      } else {
        double px = (double(pixel % out.width) + uniform(rng)) / double(out.width);
        double py = (double(pixel / out.width) + uniform(rng)) / double(out.height);
        dir = glm::normalize(forward + (2.0 * px - 1.0) * right + (1.0 - 2.0 * py) * up);
      }
      double value = 0, length = 0, tMin = 0;
      for (uint32_t depth = 1; depth <= maxDepth; ++depth) {
        auto hit = traceClosest(prepared.bvh, tris, glm::vec3(origin), glm::vec3(dir), float(tMin), INFINITY);
        if (!hit) break;
        const BvhTriangle& t = tris[hit->triangle];
        dvec3 p = (1.0 - hit->u - hit->v) * dvec3(t.p0) + double(hit->u) * dvec3(t.p1) + double(hit->v) * dvec3(t.p2);
        length += glm::length(p - origin);
        dvec3 n = normals[hit->triangle];
        const Shape& shape = scene.shapes[shapeOf[hit->triangle]];
        if (shape.emission > 0 && glm::dot(n, -dir) > 0)
          value += throughput * shape.emission * (gate ? gate(length) : 1.0);
        // Lambert: f cos / pdf = albedo with cosine sampling on the side the path arrived from.
        dvec3 side = glm::dot(n, dir) < 0 ? n : -n;
        dir = cosineDirection(side, uniform(rng), uniform(rng));
        throughput *= scene.materials[shape.material].albedo;
        origin = p;
        tMin = tEps;
      }
      sum += value;
      sumSq += value * value;
    }
    double n = spp;
    out.mean[pixel] = sum / n;
    out.variance[pixel] = n > 1 ? std::max(sumSq / n - (sum / n) * (sum / n), 0.0) / (n - 1) : 0.0;
  }
  return out;
}

}  // namespace vktg::test
