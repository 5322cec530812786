// Regularisers and preconditioners on mesh vertex positions (double precision, on the host).
#pragma once
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace vktg {

// Laplacian smoothness: weight * sum_i |V_i - mean_{j in N(i)} V_j|^2 / vertexCount, N(i) the
// vertices sharing an edge with i. Returns the energy and adds its gradient to `gradient`
// (same indexing as `positions`).
double laplacianEnergy(std::span<const glm::dvec3> positions, std::span<const glm::uvec3> triangles, double weight,
                       std::span<glm::dvec3> gradient);

// Solves (I + lambda L) x = b in place (b -> x) by conjugate gradients to relative residual 1e-10,
// L = D - A the uniform graph Laplacian of the mesh (vertexCount vertices). The "large steps"
// preconditioner (Nicolet et al. 2021).
void solveLargeSteps(std::span<const glm::uvec3> triangles, size_t vertexCount, double lambda, std::span<double> b);

}  // namespace vktg
