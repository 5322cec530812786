// What the tests of ellipsoidal connections share: the layout of tests/shaders/ellipsoid_sample.comp
// and scenes made of given triangles.
#pragma once
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "support/ellipsoid_reference.h"
#include "vktg/scene.h"

namespace vktg::test {

// One invocation of ellipsoid_sample: foci, s', the four uniforms, and the stratified number the
// choices invert (sampleEllipsoidConnectionStratified; -1: none, as sampleEllipsoidConnection).
struct EllipsoidSampleIn {
  float f1[3], f2[3], s, u[4], line;
};
// Its result: success, leaf-order triangle, point, barycentrics, weight, density at the point, and
// the triangle's vertices.
struct EllipsoidSampleOut {
  uint32_t ok, triangle;
  float position[3], bary[2], weight, density, p0[3], p1[3], p2[3], pad[2];
};
static_assert(sizeof(EllipsoidSampleIn) == 48 && sizeof(EllipsoidSampleOut) == 80);

// The statistical tests' surfaces: a 2 m square plane at z = 0 (two triangles) and a tilted
// triangle above it, with foci above both.
std::vector<RefTriangle> planeAndTiltedTriangles();
inline const dvec3 kPlaneAndTiltedFocus1{-0.3, 0.2, 1.5};
inline const dvec3 kPlaneAndTiltedFocus2{0.4, -0.1, 1.2};
// n kernel inputs with foci f1, f2: each draws its length s' from `length`, then its 4 uniforms.
std::vector<EllipsoidSampleIn> ellipsoidInputs(size_t n, uint32_t seed, dvec3 f1, dvec3 f2,
                                               const std::function<float(std::mt19937&)>& length);
// ... with the foci above the plane and the tilted triangle.
std::vector<EllipsoidSampleIn> planeAndTiltedInputs(size_t n, uint32_t seed,
                                                    const std::function<float(std::mt19937&)>& length);

// A diffuse shape made of `triangles` (float positions), one vertex triple each.
Shape shapeOfTriangles(const std::string& name, const std::vector<RefTriangle>& triangles);
// A scene of these shapes with one material and a far point light (the scene loader wants a light;
// a point light adds no triangles, so the surfaces are exactly the shapes).
Scene sceneOfShapes(std::vector<Shape> shapes);

}  // namespace vktg::test
