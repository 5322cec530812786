// Regularisers and preconditioners on mesh vertex positions (double precision, on the host), and
// their application to an experiment's parameter vector.
#pragma once
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "opt/experiment.h"

namespace vktg {

// Laplacian smoothness: weight * sum_i |V_i - mean_{j in N(i)} V_j|^2 / vertexCount, N(i) the
// vertices sharing an edge with i. Returns the energy and adds its gradient to `gradient`
// (same indexing as `positions`). Throws vktg::Error for a triangle index out of range or a
// gradient of another length.
double laplacianEnergy(std::span<const glm::dvec3> positions, std::span<const glm::uvec3> triangles, double weight,
                       std::span<glm::dvec3> gradient);

// Solves (I + lambda L) x = b in place (b -> x) by conjugate gradients to relative residual 1e-10,
// L = D - A the uniform graph Laplacian of the mesh (vertexCount vertices). The "large steps"
// preconditioner (Nicolet et al. 2021). Throws vktg::Error for a triangle index out of range, a
// negative or non-finite lambda, or (never seen in practice) no convergence in 10 n + 100 steps.
void solveLargeSteps(std::span<const glm::uvec3> triangles, size_t vertexCount, double lambda, std::span<double> b);

// The experiment's Laplacian regularisers at θ: their summed energy, with d energy / d θ added to
// `gradient` (one entry per Experiment::parameters). A regularised shape's vertices are its
// positions as written, moved by the optimised displace parameters. Translations and rotations of
// the whole shape are left out: the energy does not change under a rigid motion of the displaced
// shape (exact when the renderer applies rigid motions after displacements).
double regularization(const Experiment& experiment, const std::vector<double>& theta, std::vector<double>& gradient);

// Applies the experiment's large-steps preconditioner, if it has one, to `gradient` in place: the
// entries of the parameters that displace vertices of its shape (one vertex each, and one parameter
// per vertex and direction, checked by the parser) are gathered per vertex into one field per
// direction (0 where no parameter moves a vertex), each smoothed by solveLargeSteps and scattered
// back. Other entries are unchanged.
void preconditionGradient(const Experiment& experiment, std::vector<double>& gradient);

}  // namespace vktg
