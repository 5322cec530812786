#include "support/test_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace vktg::test {

void addQuad(Shape& shape, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3) {
  uint32_t base = uint32_t(shape.positions.size());
  shape.positions.insert(shape.positions.end(), {p0, p1, p2, p3});
  shape.triangles.push_back({base, base + 1, base + 2});
  shape.triangles.push_back({base, base + 2, base + 3});
}

void subdivideShape(Shape& shape, uint32_t levels) {
  for (uint32_t level = 0; level < levels; ++level) {
    std::vector<glm::uvec3> finer;
    finer.reserve(4 * shape.triangles.size());
    for (const glm::uvec3& t : shape.triangles) {
      uint32_t m[3];
      for (int e = 0; e < 3; ++e) {
        // Midpoints are not shared between neighbours: the surface is unchanged either way.
        m[e] = uint32_t(shape.positions.size());
        shape.positions.push_back(0.5f * (shape.positions[t[e]] + shape.positions[t[(e + 1) % 3]]));
      }
      finer.push_back({t[0], m[0], m[2]});
      finer.push_back({m[0], t[1], m[1]});
      finer.push_back({m[2], m[1], t[2]});
      finer.push_back({m[0], m[1], m[2]});
    }
    shape.triangles = std::move(finer);
  }
}

namespace {

Shape planeShape(double halfX, double halfY, uint32_t material) {
  Shape plane;
  plane.name = "plane";
  plane.material = material;
  float x = float(halfX), y = float(halfY);
  // Counter-clockwise seen from +z: the front face points up, toward sensor and light.
  addQuad(plane, {-x, -y, 0.0f}, {x, -y, 0.0f}, {x, y, 0.0f}, {-x, y, 0.0f});
  return plane;
}

Material diffuse(const char* name, double albedo) {
  Material m;
  m.name = name;
  m.type = MaterialType::Diffuse;
  m.albedo = float(albedo);
  return m;
}

// The six faces of [lo, hi] pointing inward (toward the centre); `skipFront` leaves z = hi.z open.
void addInwardBox(Shape& shape, glm::vec3 lo, glm::vec3 hi, bool skipFront) {
  glm::vec3 a = lo, b = hi;
  addQuad(shape, {a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, b.y, a.z}, {a.x, b.y, a.z});  // back z = lo: +z
  if (!skipFront) addQuad(shape, {a.x, a.y, b.z}, {a.x, b.y, b.z}, {b.x, b.y, b.z}, {b.x, a.y, b.z});  // -z
  addQuad(shape, {a.x, a.y, a.z}, {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, a.y, a.z});  // floor y = lo: +y
  addQuad(shape, {a.x, b.y, a.z}, {b.x, b.y, a.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z});  // ceiling: -y
  addQuad(shape, {a.x, a.y, a.z}, {a.x, b.y, a.z}, {a.x, b.y, b.z}, {a.x, a.y, b.z});  // left x = lo: +x
  addQuad(shape, {b.x, a.y, a.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {b.x, b.y, a.z});  // right: -x
}

// The six faces of [lo, hi] pointing outward.
void addOutwardBox(Shape& shape, glm::vec3 lo, glm::vec3 hi) {
  glm::vec3 a = lo, b = hi;
  addQuad(shape, {a.x, a.y, a.z}, {a.x, b.y, a.z}, {b.x, b.y, a.z}, {b.x, a.y, a.z});  // -z
  addQuad(shape, {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z});  // +z
  addQuad(shape, {a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, a.y, b.z}, {a.x, a.y, b.z});  // -y
  addQuad(shape, {a.x, b.y, a.z}, {a.x, b.y, b.z}, {b.x, b.y, b.z}, {b.x, b.y, a.z});  // +y
  addQuad(shape, {a.x, a.y, a.z}, {a.x, a.y, b.z}, {a.x, b.y, b.z}, {a.x, b.y, a.z});  // -x
  addQuad(shape, {b.x, a.y, a.z}, {b.x, b.y, a.z}, {b.x, b.y, b.z}, {b.x, a.y, b.z});  // +x
}

}  // namespace

Scene confocalPlaneScene(double h, double halfX, double halfY, double rho, double intensity) {
  Scene scene;
  scene.materials.push_back(diffuse("plane", rho));
  scene.shapes.push_back(planeShape(halfX, halfY, 0));
  glm::vec3 eye(0.0f, 0.0f, float(h));
  scene.pointLights.push_back({"light", eye, float(intensity)});
  scene.camera.type = CameraType::PointSensor;
  scene.camera.position = eye;
  scene.camera.normal = {0.0f, 0.0f, -1.0f};
  scene.render.maxDepth = 4;
  return scene;
}

Camera pinholeCamera(glm::vec3 position, glm::vec3 lookAt, float fovY, uint32_t resolution) {
  Camera camera;
  camera.type = CameraType::Perspective;
  camera.position = position;
  camera.lookAt = lookAt;
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.fovY = fovY;
  camera.width = camera.height = resolution;
  return camera;
}

Scene separatedPlaneScene(double d, double h0, double halfX, double halfY, double rho, double intensity,
                          glm::vec3 sensorNormal) {
  Scene scene;
  scene.materials.push_back(diffuse("plane", rho));
  scene.shapes.push_back(planeShape(halfX, halfY, 0));
  scene.pointLights.push_back({"light", {float(0.5 * d), 0.0f, float(h0)}, float(intensity)});
  scene.camera.type = CameraType::PointSensor;
  scene.camera.position = {float(-0.5 * d), 0.0f, float(h0)};
  scene.camera.normal = sensorNormal;
  scene.render.maxDepth = 4;
  return scene;
}

Scene furnaceScene(double s, double rho, double emission, bool pointSensor, uint32_t resolution) {
  Scene scene;
  scene.materials.push_back(diffuse("walls", rho));
  Shape box;
  box.name = "furnace";
  box.emission = float(emission);
  float e = float(s);
  addInwardBox(box, {-e, -e, -e}, {e, e, e}, false);
  scene.shapes.push_back(box);
  glm::vec3 eye = glm::vec3(0.1f, -0.2f, 0.3f) * e;
  glm::vec3 dir = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  scene.camera.position = eye;
  if (pointSensor) {
    scene.camera.type = CameraType::PointSensor;
    scene.camera.normal = dir;
  } else {
    scene.camera = pinholeCamera(eye, eye + dir, 60.0f, resolution);
  }
  return scene;
}

Scene cornellScene(uint32_t resolution, double emission, double pointIntensity, bool pointSensor) {
  Scene scene;
  scene.materials = {diffuse("white", 0.7), diffuse("left", 0.4), diffuse("right", 0.55), diffuse("block", 0.6)};
  Shape room;
  room.name = "room";
  room.material = 0;
  addInwardBox(room, {-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, true);
  // Recolour the side walls: they are the last two quads (four triangles) of the room.
  Shape left, right;
  left.name = "left";
  left.material = 1;
  right.name = "right";
  right.material = 2;
  addQuad(left, {-1.0f, -1.0f, -1.0f}, {-1.0f, 1.0f, -1.0f}, {-1.0f, 1.0f, 1.0f}, {-1.0f, -1.0f, 1.0f});
  addQuad(right, {1.0f, -1.0f, -1.0f}, {1.0f, -1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}, {1.0f, 1.0f, -1.0f});
  room.triangles.resize(room.triangles.size() - 4);
  scene.shapes.push_back(room);
  scene.shapes.push_back(left);
  scene.shapes.push_back(right);
  Shape block;
  block.name = "block";
  block.material = 3;
  addOutwardBox(block, {-0.5f, -1.0f, -0.6f}, {0.1f, -0.2f, 0.0f});
  scene.shapes.push_back(block);
  if (emission > 0) {
    Shape light;
    light.name = "light";
    light.material = 0;
    light.emission = float(emission);
    // Facing down (-y): counter-clockwise seen from below.
    addQuad(light, {-0.3f, 0.98f, -0.3f}, {0.3f, 0.98f, -0.3f}, {0.3f, 0.98f, 0.3f}, {-0.3f, 0.98f, 0.3f});
    scene.shapes.push_back(light);
  }
  if (pointIntensity > 0) scene.pointLights.push_back({"point", {0.4f, 0.5f, -0.7f}, float(pointIntensity)});
  if (pointSensor) {
    scene.camera.type = CameraType::PointSensor;
    scene.camera.position = {0.0f, 0.0f, 0.9f};
    scene.camera.normal = {0.0f, 0.0f, -1.0f};
  } else {
    scene.camera = pinholeCamera({0.0f, 0.0f, 3.2f}, {0.0f, 0.0f, 0.0f}, 40.0f, resolution);
  }
  return scene;
}

double gaussianWeight(double length, double mu, double sigma) {
  double z = (length - mu) / sigma;
  return std::abs(z) > kGaussianCutoff ? 0.0 : std::exp(-0.5 * z * z);
}

namespace {

constexpr int kGaussOrder = 16;

// Nodes and weights of Gauss-Legendre on [-1, 1]: Newton on P_n from the Chebyshev guesses.
struct GaussLegendre {
  std::array<double, kGaussOrder> x{}, w{};
  GaussLegendre() {
    const int n = kGaussOrder;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1;
      for (int iter = 0; iter < 100; ++iter) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          double p2 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        double step = p1 / dp;
        z -= step;
        if (std::abs(step) < 1e-16) break;
      }
      x[i] = z;
      w[i] = 2.0 / ((1 - z * z) * dp * dp);
    }
  }
};

const double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

double integrate(const std::function<double(double)>& f, double a, double b, int panels) {
  static const GaussLegendre rule;
  if (!(b > a)) return 0.0;
  double width = (b - a) / panels, sum = 0;
  for (int p = 0; p < panels; ++p) {
    double centre = a + (p + 0.5) * width;
    for (int i = 0; i < kGaussOrder; ++i) sum += rule.w[i] * f(centre + 0.5 * width * rule.x[i]);
  }
  return 0.5 * width * sum;
}

double confocalBox(double h, double rho, double intensity, double a, double b) {
  double d1 = std::max(h, 0.5 * a), d2 = std::max(h, 0.5 * b);
  return 0.4 * rho * intensity * h * h * h * (std::pow(d1, -5.0) - std::pow(d2, -5.0));
}

double confocalGated(double h, double rho, double intensity, const std::function<double(double)>& gate,
                     double lo, double hi) {
  double dLo = std::max(h, 0.5 * lo), dHi = 0.5 * hi;
  auto integrand = [&](double d) { return std::pow(d, -6.0) * gate(2.0 * d); };
  return 2.0 * rho * intensity * h * h * h * integrate(integrand, dLo, dHi, 256);
}

double confocalSteadySquare(double h, double halfSize, double rho, double intensity) {
  auto integrand = [&](double theta) {
    double c = std::cos(theta);
    return std::pow(h, -5.0) - std::pow(h * h + halfSize * halfSize / (c * c), -2.5);
  };
  return 8.0 * rho * intensity * h * h * h / (5.0 * std::numbers::pi) * integrate(integrand, 0.0, 0.25 * std::numbers::pi, 64);
}

double separatedPlaneShortest(double d, double h0) { return std::sqrt(d * d + 4.0 * h0 * h0); }

double separatedPlaneDensity(const SeparatedPlane& p, double u) {
  const double d = p.d, h0 = p.h0;
  if (!(u > separatedPlaneShortest(d, h0))) return 0.0;
  double a = 0.5 * u, b = 0.5 * std::sqrt((u - d) * (u + d));
  double k2 = std::max(0.0, (b - h0) * (b + h0) / (b * b)), k = std::sqrt(k2);
  double da = 0.5, db = u / (4.0 * b), kdk = h0 * h0 * db / (b * b * b);
  double jc = da * b * k2 + a * b * kdk, js = a * db * k2 + a * b * kdk;
  const int n = 16384;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double phi = kTwoPi * (i + 0.5) / n, c = std::cos(phi), s = std::sin(phi);
    double x = a * k * c, y = b * k * s;
    if (std::abs(x) > p.halfX || std::abs(y) > p.halfY) continue;
    glm::dvec3 toA(x + 0.5 * d, y, -h0);  // x - A
    double ra2 = glm::dot(toA, toA);
    double rb2 = (x - 0.5 * d) * (x - 0.5 * d) + y * y + h0 * h0;
    double f = h0 * h0 * std::max(0.0, glm::dot(p.normal, toA)) / (ra2 * ra2 * rb2 * std::sqrt(rb2));
    sum += f * (c * c * jc + s * s * js);
  }
  return p.rho * p.intensity / std::numbers::pi * sum * kTwoPi / n;
}

double separatedPlaneGated(const SeparatedPlane& p, const std::function<double(double)>& gate, double lo, double hi) {
  double uMin = separatedPlaneShortest(p.d, p.h0);
  double tLo = std::sqrt(std::max(0.0, lo - uMin)), tHi = std::sqrt(std::max(0.0, hi - uMin));
  auto integrand = [&](double t) {
    double u = uMin + t * t;
    return 2.0 * t * gate(u) * separatedPlaneDensity(p, u);
  };
  return integrate(integrand, tLo, tHi, 128);
}

double separatedPlaneGaussianFloat(const SeparatedPlane& p, double mu, double sigma) {
  double lo = mu - kGaussianCutoff * sigma, hi = mu + kGaussianCutoff * sigma;
  // Integral of the gaussian W from mu to x.
  auto primitive = [&](double x) {
    double z = std::clamp((x - mu) / sigma, -kGaussianCutoff, kGaussianCutoff);
    return sigma * std::sqrt(0.5 * std::numbers::pi) * std::erf(z / std::sqrt(2.0));
  };
  double sum = 0;
  float s = std::nextafter(float(lo), -INFINITY);
  while (double(s) <= hi) {
    double below = 0.5 * (double(s) + double(std::nextafter(s, -INFINITY)));
    double above = 0.5 * (double(s) + double(std::nextafter(s, INFINITY)));
    sum += separatedPlaneDensity(p, double(s)) * (primitive(above) - primitive(below));
    s = std::nextafter(s, INFINITY);
  }
  return sum;
}

double sceneDiagonal(const Scene& scene) {
  glm::vec3 lo, hi;
  sceneBounds(scene, lo, hi);
  return double(glm::length(hi - lo));
}

}  // namespace vktg::test
