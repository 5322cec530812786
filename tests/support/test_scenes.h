// C++ builders of the small scenes the render tests use (render_*, hard_render), and the exact
// responses of the plane scenes (closed forms and double-precision quadratures). Every scene is
// diffuse only; the comments give the geometry the closed forms assume.
#pragma once
#include <functional>

#include <glm/glm.hpp>

#include "vktg/scene.h"

namespace vktg::test {

// Appends the quad p0 p1 p2 p3 (a planar convex polygon in that order) as two triangles whose
// front face (the emitting side) is normalize(cross(p1 - p0, p2 - p0)).
void addQuad(Shape& shape, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3);

// Splits every triangle of `shape` into four at its edge midpoints, `levels` times (4^levels times
// the triangles, the same surface): scenes whose tessellation, not geometry, grows.
void subdivideShape(Shape& shape, uint32_t levels);

// A perspective camera at `position` looking at `lookAt` (up +y), vertical field of view fovY
// degrees, resolution x resolution pixels.
Camera pinholeCamera(glm::vec3 position, glm::vec3 lookAt, float fovY, uint32_t resolution);

// Confocal plane: the rectangle |x| <= halfX, |y| <= halfY of the plane z = 0 (front face +z,
// albedo rho), a point sensor at (0, 0, h) looking down (-z) and a point light of intensity I at the
// same point. Steady gate; maxDepth 4 (one bounce is all a single plane allows).
Scene confocalPlaneScene(double h, double halfX, double halfY, double rho, double intensity);

// Separated sensor and light above the plane z = 0: sensor at (-d/2, 0, h0) with the given normal,
// light at (+d/2, 0, h0), plane rectangle |x| <= halfX, |y| <= halfY (front +z, albedo rho).
Scene separatedPlaneScene(double d, double h0, double halfX, double halfY, double rho, double intensity,
                          glm::vec3 sensorNormal = {0.0f, 0.0f, -1.0f});

// Furnace: the cube [-s, s]^3, every face pointing inward, albedo rho, emitting Le on every face.
// A point sensor at (0.1, -0.2, 0.3) looking along (0.3, 0.2, -1) (pointSensor), else a perspective
// camera there looking the same way (resolution x resolution, 60 degrees).
Scene furnaceScene(double s, double rho, double emission, bool pointSensor, uint32_t resolution);

// A small Cornell-like room: the box [-1, 1]^3 with the front face (z = +1) open, walls pointing
// inward (albedo 0.7, left wall 0.4, right wall 0.55), a block on the floor (albedo 0.6), a quad light
// of radiance `emission` just below the ceiling facing down, and a point light of intensity
// `pointIntensity` (none if 0) near the back wall. Perspective camera at (0, 0, 3.2) looking at the
// origin (resolution x resolution), or a point sensor at (0, 0, 0.9) looking at -z.
Scene cornellScene(uint32_t resolution, double emission, double pointIntensity, bool pointSensor);

// Path-length importance of a gaussian gate as the spec defines it (THEORY.md §1, gate.h):
// exp(-(L - mu)^2 / (2 sigma^2)) within kGaussianCutoff sigma of mu, 0 beyond.
double gaussianWeight(double length, double mu, double sigma);

// Composite 16-point Gauss-Legendre quadrature of f over [a, b] in `panels` equal panels.
double integrate(const std::function<double(double)>& f, double a, double b, int panels);

// Confocal plane (infinite, albedo rho, light intensity I, height h). A plane point at distance d
// from the sensor is lit with irradiance I (h/d) / d^2, reflects radiance rho/pi of that, and is
// seen under cos = h/d at the sensor through solid angle dA (h/d) / d^2: it contributes
// rho I h^3 / (pi d^7) dA at path length 2d. With dA = 2 pi r dr = 2 pi d dd (r^2 = d^2 - h^2),
//   M[W] = 2 rho I h^3 * integral_h^inf d^-6 W(2d) dd.
// Box gate [a, b]: M = (2/5) rho I h^3 (d1^-5 - d2^-5), d1 = max(h, a/2), d2 = max(h, b/2).
double confocalBox(double h, double rho, double intensity, double a, double b);
// Any gate W supported on [lo, hi] (path lengths), by quadrature in d.
double confocalGated(double h, double rho, double intensity, const std::function<double(double)>& gate,
                     double lo, double hi);
// Steady response of the square |x|, |y| <= R (not infinite): in polar coordinates over the eight
// triangles 0 <= theta <= pi/4, r <= R / cos(theta), the radial integral of
// rho I h^3 r / (pi (r^2 + h^2)^(7/2)) is closed, leaving
//   (8 rho I h^3 / (5 pi)) integral_0^{pi/4} [h^-5 - (h^2 + R^2 / cos^2 theta)^(-5/2)] dtheta,
// which tends to 2 rho I / (5 h^2) as R -> infinity.
double confocalSteadySquare(double h, double halfSize, double rho, double intensity);

// Separated plane (sensor at A = (-D/2, 0, h0) with unit normal n, light at B = (D/2, 0, h0)). A
// plane point x is lit with irradiance I h0 / |x-B|^3, reflects rho/pi of it toward A under cos
// h0/|x-A|, and is seen under cos n.(x-A)/|x-A| through solid angle dA / |x-A|^2 (the cosine at x
// converts dA): f(x) = rho I h0^2 max(0, n.(x-A)) / (pi |x-A|^4 |x-B|^3). The points with path
// length u lie on the ellipse X = a k cos(phi), Y = b k sin(phi), a = u/2, b = sqrt((u-D)(u+D))/2,
// k^2 = 1 - h0^2/b^2 (the spheroid with foci A, B cut by z = 0), so dA = J du dphi with
//   J = cos^2(phi) (a' b k^2 + a b k k') + sin^2(phi) (a b' k^2 + a b k k'),
// a' = 1/2, b' = u / (4b), k k' = h0^2 b' / b^3 (finite as k -> 0). The response per unit path
// length M(u) = integral_0^{2 pi} f J dphi (trapezoid, periodic) is 0 below the shortest path
// uMin = sqrt(D^2 + 4 h0^2). Points outside the plane rectangle |X| <= halfX, |Y| <= halfY add
// nothing (the trapezoid rule then converges like 1/n only: n = 16384 points).
struct SeparatedPlane {
  double d, h0, halfX, halfY, rho, intensity;
  glm::dvec3 normal{0.0, 0.0, -1.0};
};
double separatedPlaneDensity(const SeparatedPlane& p, double u);
double separatedPlaneShortest(double d, double h0);
// Integral of W(u) M(u) over [lo, hi] (W's support), with u = uMin + t^2 to absorb M's square-root
// behaviour at uMin.
double separatedPlaneGated(const SeparatedPlane& p, const std::function<double(double)>& gate, double lo, double hi);
// The same for a gaussian gate (mu, sigma) as an estimator sees it that draws the length s from the
// gate and evaluates at the float32 nearest to s (a GPU length is a float): the integral of
// W(s) M(float(s)) ds = sum over floats s_k of M(s_k) times the integral of W over the lengths that
// round to s_k. It differs from the exact value where M changes within an ulp (at uMin when the
// ellipsoid is only ~1e-6 longer than the focal distance).
double separatedPlaneGaussianFloat(const SeparatedPlane& p, double mu, double sigma);

// Axis-aligned bounds' diagonal (shapes, lights and camera): every segment of a path inside the
// bounds is at most this long.
double sceneDiagonal(const Scene& scene);

}  // namespace vktg::test
