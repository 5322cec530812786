// Laplacian smoothness and the large-steps preconditioner on the uniform graph Laplacian of a
// triangle mesh. Both walk the mesh's vertex adjacency, built in O(triangles) as compressed rows,
// so a 1000 x 1000 heightfield costs milliseconds per call.
#include "opt/regularizer.h"

#include <algorithm>
#include <cmath>

#include "vktg/error.h"

namespace vktg {
namespace {

constexpr double kRelativeResidual = 1e-10;

// The vertices sharing an edge with each vertex: neighbours of v are indices[offsets[v] ..
// offsets[v + 1]), sorted, each once.
struct Adjacency {
  std::vector<size_t> offsets;
  std::vector<uint32_t> indices;
  size_t degree(size_t v) const { return offsets[v + 1] - offsets[v]; }
};

Adjacency buildAdjacency(std::span<const glm::uvec3> triangles, size_t vertexCount, const char* caller) {
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      if (triangles[t][c] >= vertexCount)
        fail("", caller, "triangle " + std::to_string(t) + " names vertex " + std::to_string(triangles[t][c]) +
                             " of a mesh with " + std::to_string(vertexCount) + " vertices");
  // Every triangle gives each of its corners the other two as neighbours (with repeats, which the
  // per-vertex sort below removes; a degenerate triangle's repeated corner is no neighbour).
  std::vector<size_t> counts(vertexCount + 1, 0);
  for (const glm::uvec3& tri : triangles)
    for (int c = 0; c < 3; ++c) counts[tri[c] + 1] += 2;
  for (size_t v = 0; v < vertexCount; ++v) counts[v + 1] += counts[v];
  std::vector<uint32_t> all(counts.back());
  std::vector<size_t> fill(counts.begin(), counts.end() - 1);
  for (const glm::uvec3& tri : triangles)
    for (int c = 0; c < 3; ++c) {
      all[fill[tri[c]]++] = tri[(c + 1) % 3];
      all[fill[tri[c]]++] = tri[(c + 2) % 3];
    }
  Adjacency adjacency;
  adjacency.offsets.assign(vertexCount + 1, 0);
  adjacency.indices.reserve(all.size() / 2);
  for (size_t v = 0; v < vertexCount; ++v) {
    const auto begin = all.begin() + std::ptrdiff_t(counts[v]), end = all.begin() + std::ptrdiff_t(counts[v + 1]);
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it)
      if (*it != v && (it == begin || *it != *(it - 1))) adjacency.indices.push_back(*it);
    adjacency.offsets[v + 1] = adjacency.indices.size();
  }
  return adjacency;
}

// y = (I + lambda L) x, L = D - A.
void applySystem(const Adjacency& adjacency, double lambda, const std::vector<double>& x, std::vector<double>& y) {
  for (size_t v = 0; v < x.size(); ++v) {
    double neighbours = 0;
    for (size_t k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) neighbours += x[adjacency.indices[k]];
    y[v] = x[v] + lambda * (double(adjacency.degree(v)) * x[v] - neighbours);
  }
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

// Calls `visit(parameter index, scene parameter)` for every optimised displace parameter of `shape`.
template <typename Visit>
void forEachDisplacement(const Experiment& experiment, uint32_t shape, Visit visit) {
  const std::string& name = experiment.scene.shapes.at(shape).name;
  for (size_t i = 0; i < experiment.parameters.size(); ++i) {
    const Parameter& p = experiment.scene.parameters[experiment.parameters[i].sceneIndex];
    if (p.kind == ParameterKind::Displace && p.target == name) visit(i, p);
  }
}

void requireLength(const char* what, size_t size, size_t expected) {
  if (size != expected)
    fail("", what, "got " + std::to_string(size) + " values for " + std::to_string(expected) + " parameters");
}

}  // namespace

double laplacianEnergy(std::span<const glm::dvec3> positions, std::span<const glm::uvec3> triangles, double weight,
                       std::span<glm::dvec3> gradient) {
  const size_t count = positions.size();
  if (gradient.size() != count)
    fail("", "laplacian", "gradient has " + std::to_string(gradient.size()) + " entries for " + std::to_string(count) +
                              " vertices");
  if (count == 0) return 0;
  const Adjacency adjacency = buildAdjacency(triangles, count, "laplacian");
  // delta_i = V_i - mean of its neighbours (0 for an isolated vertex).
  std::vector<glm::dvec3> delta(count, glm::dvec3(0.0));
  double energy = 0;
  for (size_t v = 0; v < count; ++v) {
    const size_t degree = adjacency.degree(v);
    if (degree == 0) continue;
    glm::dvec3 sum(0.0);
    for (size_t k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) sum += positions[adjacency.indices[k]];
    delta[v] = positions[v] - sum / double(degree);
    energy += glm::dot(delta[v], delta[v]);
  }
  // dE/dV_j = 2 w / n (delta_j - sum over i with j in N(i) of delta_i / deg(i)).
  const double scale = 2.0 * weight / double(count);
  for (size_t v = 0; v < count; ++v) {
    const size_t degree = adjacency.degree(v);
    if (degree == 0) continue;
    gradient[v] += scale * delta[v];
    const glm::dvec3 share = scale * delta[v] / double(degree);
    for (size_t k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) gradient[adjacency.indices[k]] -= share;
  }
  return weight * energy / double(count);
}

void solveLargeSteps(std::span<const glm::uvec3> triangles, size_t vertexCount, double lambda, std::span<double> b) {
  if (b.size() != vertexCount)
    fail("", "large_steps", "right-hand side has " + std::to_string(b.size()) + " entries for " +
                                std::to_string(vertexCount) + " vertices");
  if (!(lambda >= 0) || !std::isfinite(lambda)) fail("", "large_steps", "lambda must be finite and >= 0");
  const Adjacency adjacency = buildAdjacency(triangles, vertexCount, "large_steps");
  const size_t n = vertexCount;
  // Conjugate gradients from x = 0, preconditioned by the diagonal 1 + lambda deg(v) (Jacobi).
  std::vector<double> x(n, 0.0), r(b.begin(), b.end()), z(n), p(n), q(n);
  const double target = kRelativeResidual * std::sqrt(dot(r, r));
  if (target == 0) return;  // b = 0: x = 0 = b
  for (size_t v = 0; v < n; ++v) z[v] = r[v] / (1.0 + lambda * double(adjacency.degree(v)));
  p = z;
  double rz = dot(r, z);
  const size_t maxIterations = 10 * n + 100;
  for (size_t iteration = 0; std::sqrt(dot(r, r)) > target; ++iteration) {
    if (iteration == maxIterations)
      fail("", "large_steps", "conjugate gradients did not converge in " + std::to_string(maxIterations) + " steps");
    applySystem(adjacency, lambda, p, q);
    const double alpha = rz / dot(p, q);
    for (size_t v = 0; v < n; ++v) {
      x[v] += alpha * p[v];
      r[v] -= alpha * q[v];
      z[v] = r[v] / (1.0 + lambda * double(adjacency.degree(v)));
    }
    const double next = dot(r, z);
    const double beta = next / rz;
    rz = next;
    for (size_t v = 0; v < n; ++v) p[v] = z[v] + beta * p[v];
  }
  std::copy(x.begin(), x.end(), b.begin());
}

double regularization(const Experiment& experiment, const std::vector<double>& theta, std::vector<double>& gradient) {
  requireLength("regularization: theta", theta.size(), experiment.parameters.size());
  requireLength("regularization: gradient", gradient.size(), experiment.parameters.size());
  double energy = 0;
  for (const RegularizerSpec& spec : experiment.regularizers) {
    const Shape& shape = experiment.scene.shapes.at(spec.shape);
    std::vector<glm::dvec3> positions(shape.positions.begin(), shape.positions.end());
    forEachDisplacement(experiment, spec.shape, [&](size_t i, const Parameter& p) {
      for (uint32_t v : p.vertices) positions[v] += theta[i] * glm::dvec3(p.axis);
    });
    std::vector<glm::dvec3> vertexGradient(positions.size(), glm::dvec3(0.0));
    energy += laplacianEnergy(positions, shape.triangles, spec.weight, vertexGradient);
    forEachDisplacement(experiment, spec.shape, [&](size_t i, const Parameter& p) {
      for (uint32_t v : p.vertices) gradient[i] += glm::dot(vertexGradient[v], glm::dvec3(p.axis));
    });
  }
  return energy;
}

void preconditionGradient(const Experiment& experiment, std::vector<double>& gradient) {
  if (!experiment.preconditioner) return;
  requireLength("preconditioner: gradient", gradient.size(), experiment.parameters.size());
  const PreconditionerSpec& spec = *experiment.preconditioner;
  const Shape& shape = experiment.scene.shapes.at(spec.shape);
  // One field per direction: (I + λ L)⁻¹ acts on each coordinate of a displacement alone, so the
  // x, y and z parameters of free vertex positions are smoothed as the xyz field they make.
  struct Entry {
    size_t parameter;
    uint32_t vertex;
    size_t direction;
  };
  std::vector<glm::vec3> directions;
  std::vector<Entry> entries;
  forEachDisplacement(experiment, spec.shape, [&](size_t i, const Parameter& p) {
    if (p.vertices.size() != 1)
      fail("", "preconditioner", "parameter \"" + p.name + "\" displaces " + std::to_string(p.vertices.size()) +
                                     " vertices; large steps needs one vertex per parameter");
    const glm::vec3 direction = glm::normalize(p.axis);  // heights: the heightfield's scaled up
    auto it = std::find(directions.begin(), directions.end(), direction);
    if (it == directions.end()) it = directions.insert(directions.end(), direction);
    entries.push_back({i, p.vertices.front(), size_t(it - directions.begin())});
  });
  for (size_t d = 0; d < directions.size(); ++d) {
    std::vector<double> perVertex(shape.positions.size(), 0.0);
    for (const Entry& e : entries)
      if (e.direction == d) perVertex[e.vertex] = gradient[e.parameter];
    solveLargeSteps(shape.triangles, perVertex.size(), spec.lambda, perVertex);
    for (const Entry& e : entries)
      if (e.direction == d) gradient[e.parameter] = perVertex[e.vertex];
  }
}

}  // namespace vktg
