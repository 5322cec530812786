// Pearson chi-square goodness-of-fit tests for the project's samplers (BSDFs, lights, gates,
// ellipsoidal connections): histogram the samples, integrate the claimed density over each cell
// in double precision, pool sparse cells, and compare. A failed draw (a sampler returning "no
// sample") is a legitimate outcome: its expected probability is 1 minus the density's integral, so
// the tests also catch densities that claim too much or too little mass.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace vktg::test {

struct Chi2Options {
  double significance = 0.01;  // family-wise false-failure rate
  int testCount = 1;           // tests sharing that rate (Sidak correction)
  double minExpected = 5.0;    // cells below this expected count are pooled
};

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double pValue = 1.0;
  double level = 0.0;          // per-test significance after the Sidak correction
  double densityMass = 0.0;    // integral of the density over the domain
  bool passed = false;
  std::string report;          // statistic, worst cells, and (2D) a residual map: print on failure
};

// Per-test level so that `testCount` independent tests falsely fail together with `familyLevel`.
double sidakLevel(double familyLevel, int testCount);
// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a).
double regularizedGammaQ(double a, double x);
// P(X >= statistic) for X ~ chi-square with `dof` degrees of freedom.
double chi2PValue(double statistic, int dof);

// Pearson test on arbitrary cells; the total of `observed` is the sample count. `cellName(i)` labels
// cell i in the report. A cell with zero expectation but observations fails outright.
Chi2Result pearsonChi2(const std::vector<double>& observed, const std::vector<double>& expected,
                       const Chi2Options& options, const std::function<std::string(size_t)>& cellName);

// A rectangle [x0, x1] x [y0, y1] cut into nx * ny cells; cell index iy * nx + ix.
struct Grid2D {
  double x0, x1, y0, y1;
  int nx, ny;
  int cellOf(double x, double y) const;  // -1 outside
};

// Integral of `density` over each cell: nested adaptive Simpson (each cell split 4 x 4 first so
// narrow peaks are not stepped over), absolute tolerance `tolerance` per cell.
std::vector<double> integrateGrid(const Grid2D& grid, const std::function<double(double, double)>& density,
                                  double tolerance);

// 2D test on `grid`: `samples` are the successful draws as (x, y), `totalDraws` counts failed draws
// too. `density` is with respect to dx dy.
Chi2Result chi2Test2D(const Grid2D& grid, const std::vector<glm::dvec2>& samples, size_t totalDraws,
                      const std::function<double(double, double)>& density, const Chi2Options& options);

// Directions on the unit sphere, binned in (cos theta = z, phi) so cells have equal solid angle;
// `pdf` is the solid-angle density. nCos should be even so that z = 0 is a cell boundary.
Chi2Result chi2Sphere(const std::vector<glm::dvec3>& samples, size_t totalDraws,
                      const std::function<double(const glm::dvec3&)>& pdf, int nCos, int nPhi,
                      const Chi2Options& options);

// 1D test on [a, b] with `bins` equal cells (used for gate sampling).
Chi2Result chi2Test1D(const std::vector<double>& samples, size_t totalDraws, double a, double b, int bins,
                      const std::function<double(double)>& density, const Chi2Options& options);

}  // namespace vktg::test
