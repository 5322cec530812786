#include "support/chi2.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <sstream>

namespace vktg::test {
namespace {

// Adaptive Simpson on [a, b] given the end and mid values; `whole` is the Simpson estimate.
template <class F>
double simpsonAdaptive(const F& f, double a, double b, double fa, double fm, double fb, double whole,
                       double tolerance, int depth) {
  double m = 0.5 * (a + b);
  double lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  double flm = f(lm), frm = f(rm);
  double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  double delta = left + right - whole;
  if (depth <= 0 || std::abs(delta) <= 15.0 * tolerance) return left + right + delta / 15.0;
  return simpsonAdaptive(f, a, m, fa, flm, fm, left, 0.5 * tolerance, depth - 1) +
         simpsonAdaptive(f, m, b, fm, frm, fb, right, 0.5 * tolerance, depth - 1);
}

// [a, b] split into `pieces` first, then refined adaptively.
template <class F>
double integrate1D(const F& f, double a, double b, double tolerance, int pieces) {
  double sum = 0.0;
  double h = (b - a) / pieces;
  for (int i = 0; i < pieces; ++i) {
    double lo = a + i * h, hi = (i + 1 == pieces) ? b : lo + h;
    double flo = f(lo), fhi = f(hi), fm = f(0.5 * (lo + hi));
    double whole = (hi - lo) / 6.0 * (flo + 4.0 * fm + fhi);
    sum += simpsonAdaptive(f, lo, hi, flo, fm, fhi, whole, tolerance / pieces, 18);
  }
  return sum;
}

// Q(a, x) by its power series of P (x < a + 1) or Lentz's continued fraction (otherwise).
double gammaQSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 100000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * 1e-16) break;
  }
  double p = sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
  return std::clamp(1.0 - p, 0.0, 1.0);
}

double gammaQContinuedFraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return std::clamp(std::exp(-x + a * std::log(x) - std::lgamma(a)) * h, 0.0, 1.0);
}

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), format, a, b, c, d);
  return buf;
}

// Appends a residual map: one character per cell, sign and size of (obs - exp) / sqrt(exp).
void appendResidualMap(std::string& report, const std::vector<double>& observed, const std::vector<double>& expected,
                       int nx, int ny, const char* xLabel, const char* yLabel) {
  std::ostringstream out;
  out << "residual map (rows: " << yLabel << " ascending, columns: " << xLabel
      << "; '.' |z|<2, '+'/'-' 2..4, '#'/'=' >4 more/fewer than expected, '!' samples where none expected):\n";
  for (int iy = 0; iy < ny; ++iy) {
    out << "  ";
    for (int ix = 0; ix < nx; ++ix) {
      size_t i = size_t(iy) * nx + ix;
      double e = expected[i], o = observed[i];
      char ch = '.';
      if (e <= 0.0) {
        ch = o > 0.0 ? '!' : ' ';
      } else {
        double z = (o - e) / std::sqrt(e);
        if (z > 4.0) ch = '#';
        else if (z > 2.0) ch = '+';
        else if (z < -4.0) ch = '=';
        else if (z < -2.0) ch = '-';
      }
      out << ch;
    }
    out << "\n";
  }
  report += out.str();
}

}  // namespace

double sidakLevel(double familyLevel, int testCount) {
  return -std::expm1(std::log1p(-familyLevel) / std::max(testCount, 1));
}

double regularizedGammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  return x < a + 1.0 ? gammaQSeries(a, x) : gammaQContinuedFraction(a, x);
}

double chi2PValue(double statistic, int dof) {
  if (dof <= 0) return 1.0;
  return regularizedGammaQ(0.5 * dof, 0.5 * statistic);
}

Chi2Result pearsonChi2(const std::vector<double>& observed, const std::vector<double>& expected,
                       const Chi2Options& options, const std::function<std::string(size_t)>& cellName) {
  Chi2Result r;
  r.level = sidakLevel(options.significance, options.testCount);
  std::ostringstream rep;
  size_t n = observed.size();
  double total = std::accumulate(observed.begin(), observed.end(), 0.0);
  double totalExpected = std::accumulate(expected.begin(), expected.end(), 0.0);

  // Samples in a cell the density says is empty cannot be explained by chance.
  size_t impossible = 0;
  for (size_t i = 0; i < n; ++i) {
    if (expected[i] <= 0.0 && observed[i] > 0.0) {
      if (impossible < 10) rep << "  " << observed[i] << " samples in " << cellName(i) << " where the density is 0\n";
      ++impossible;
    }
  }

  // Pool every sparse cell into one; if the pool is still sparse, merge it with the smallest cell.
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double poolObs = 0.0, poolExp = 0.0;
  size_t first = 0;
  auto pool = [&] {
    poolObs += observed[order[first]];
    poolExp += expected[order[first]];
    ++first;
  };
  while (first < n && expected[order[first]] < options.minExpected) pool();
  while (first < n && poolExp > 0.0 && poolExp < options.minExpected) pool();

  struct Contribution {
    double value, obs, exp;
    std::string name;
  };
  std::vector<Contribution> parts;
  int cells = 0;
  auto add = [&](double o, double e, std::string name) {
    double c = (o - e) * (o - e) / e;
    r.statistic += c;
    ++cells;
    parts.push_back({c, o, e, std::move(name)});
  };
  if (poolExp > 0.0) add(poolObs, poolExp, "pool of " + std::to_string(first) + " sparse cells");
  for (size_t k = first; k < n; ++k) add(observed[order[k]], expected[order[k]], cellName(order[k]));
  r.dof = cells - 1;
  r.pValue = chi2PValue(r.statistic, r.dof);
  r.passed = impossible == 0 && r.dof > 0 && r.pValue >= r.level;

  std::ostringstream head;
  head << "chi-square " << r.statistic << " with " << r.dof << " dof: p = " << r.pValue << " (level " << r.level
       << "); samples " << total << ", expected total " << totalExpected << ", pooled cells " << first;
  if (impossible > 0) head << "; " << impossible << " cells with samples where the density is 0";
  head << "\nlargest contributions:\n";
  std::sort(parts.begin(), parts.end(), [](const Contribution& a, const Contribution& b) { return a.value > b.value; });
  for (size_t k = 0; k < std::min<size_t>(parts.size(), 8); ++k)
    head << "  " << parts[k].name << fmt(": observed %.0f expected %.2f (chi2 %.2f)\n", parts[k].obs, parts[k].exp,
                                         parts[k].value);
  r.report = head.str() + rep.str();
  return r;
}

int Grid2D::cellOf(double x, double y) const {
  if (!(x >= x0 && x <= x1 && y >= y0 && y <= y1)) return -1;
  int ix = std::min(nx - 1, int((x - x0) / (x1 - x0) * nx));
  int iy = std::min(ny - 1, int((y - y0) / (y1 - y0) * ny));
  return iy * nx + ix;
}

std::vector<double> integrateGrid(const Grid2D& grid, const std::function<double(double, double)>& density,
                                  double tolerance) {
  std::vector<double> cells(size_t(grid.nx) * grid.ny);
  double hx = (grid.x1 - grid.x0) / grid.nx, hy = (grid.y1 - grid.y0) / grid.ny;
  for (int iy = 0; iy < grid.ny; ++iy) {
    double ya = grid.y0 + iy * hy, yb = iy + 1 == grid.ny ? grid.y1 : ya + hy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      double xa = grid.x0 + ix * hx, xb = ix + 1 == grid.nx ? grid.x1 : xa + hx;
      // The inner integral's error is multiplied by the outer width: share the tolerance accordingly.
      double innerTolerance = 0.5 * tolerance / (yb - ya);
      auto inner = [&](double y) {
        return integrate1D([&](double x) { return density(x, y); }, xa, xb, innerTolerance, 4);
      };
      cells[size_t(iy) * grid.nx + ix] = integrate1D(inner, ya, yb, 0.5 * tolerance, 4);
    }
  }
  return cells;
}

namespace {

// Histogram + expected counts + the extra "no sample" cell, then Pearson.
Chi2Result finish2D(const Grid2D& grid, std::vector<double> observed, size_t failed, size_t totalDraws,
                    const std::vector<double>& probabilities, const Chi2Options& options, const char* xLabel,
                    const char* yLabel) {
  double mass = std::accumulate(probabilities.begin(), probabilities.end(), 0.0);
  std::vector<double> expected(probabilities.size());
  for (size_t i = 0; i < expected.size(); ++i) expected[i] = probabilities[i] * double(totalDraws);
  std::vector<double> obs = observed, exp = expected;
  obs.push_back(double(failed));
  exp.push_back(std::max(0.0, 1.0 - mass) * double(totalDraws));
  size_t noSample = obs.size() - 1;
  Chi2Result r = pearsonChi2(obs, exp, options, [&](size_t i) {
    if (i == noSample) return std::string("'no sample'");
    int ix = int(i % grid.nx), iy = int(i / grid.nx);
    double hx = (grid.x1 - grid.x0) / grid.nx, hy = (grid.y1 - grid.y0) / grid.ny;
    return std::string("cell ") + xLabel + fmt(" [%.4g, %.4g) ", grid.x0 + ix * hx, grid.x0 + (ix + 1) * hx) +
           yLabel + fmt(" [%.4g, %.4g)", grid.y0 + iy * hy, grid.y0 + (iy + 1) * hy);
  });
  r.densityMass = mass;
  r.report += fmt("density integral %.6f, draws without a sample %.0f of %.0f\n", mass, double(failed), double(totalDraws));
  appendResidualMap(r.report, observed, expected, grid.nx, grid.ny, xLabel, yLabel);
  return r;
}

}  // namespace

Chi2Result chi2Test2D(const Grid2D& grid, const std::vector<glm::dvec2>& samples, size_t totalDraws,
                      const std::function<double(double, double)>& density, const Chi2Options& options) {
  std::vector<double> observed(size_t(grid.nx) * grid.ny, 0.0);
  size_t outside = 0;
  for (const glm::dvec2& s : samples) {
    int c = grid.cellOf(s.x, s.y);
    if (c < 0) ++outside;
    else observed[c] += 1.0;
  }
  double tolerance = 1e-3 / double(std::max<size_t>(totalDraws, 1));
  Chi2Result r = finish2D(grid, observed, totalDraws - samples.size(), totalDraws,
                          integrateGrid(grid, density, tolerance), options, "x", "y");
  if (outside > 0) {
    r.passed = false;
    r.report = std::to_string(outside) + " samples outside the domain\n" + r.report;
  }
  return r;
}

Chi2Result chi2Sphere(const std::vector<glm::dvec3>& samples, size_t totalDraws,
                      const std::function<double(const glm::dvec3&)>& pdf, int nCos, int nPhi,
                      const Chi2Options& options) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  Grid2D grid{0.0, kTwoPi, -1.0, 1.0, nPhi, nCos};
  std::vector<double> observed(size_t(nCos) * nPhi, 0.0);
  size_t invalid = 0;
  for (const glm::dvec3& d : samples) {
    double len = glm::length(d);
    if (!(std::abs(len - 1.0) < 1e-4)) {
      ++invalid;
      continue;
    }
    glm::dvec3 w = d / len;
    double phi = std::atan2(w.y, w.x);
    if (phi < 0.0) phi += kTwoPi;
    observed[grid.cellOf(phi, std::clamp(w.z, -1.0, 1.0))] += 1.0;
  }
  // (z, phi) is an equal-area parameterisation: the solid-angle density needs no Jacobian.
  auto density = [&](double phi, double z) {
    double r = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
    return pdf(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
  };
  double tolerance = 1e-3 / double(std::max<size_t>(totalDraws, 1));
  Chi2Result r = finish2D(grid, observed, totalDraws - samples.size(), totalDraws,
                          integrateGrid(grid, density, tolerance), options, "phi", "cos theta");
  if (invalid > 0) {
    r.passed = false;
    r.report = std::to_string(invalid) + " samples are not unit vectors\n" + r.report;
  }
  return r;
}

Chi2Result chi2Test1D(const std::vector<double>& samples, size_t totalDraws, double a, double b, int bins,
                      const std::function<double(double)>& density, const Chi2Options& options) {
  std::vector<double> observed(bins, 0.0), probabilities(bins);
  size_t outside = 0;
  for (double s : samples) {
    if (!(s >= a && s <= b)) {
      ++outside;
      continue;
    }
    observed[std::min(bins - 1, int((s - a) / (b - a) * bins))] += 1.0;
  }
  double h = (b - a) / bins;
  double tolerance = 1e-3 / double(std::max<size_t>(totalDraws, 1));
  for (int i = 0; i < bins; ++i)
    probabilities[i] = integrate1D(density, a + i * h, i + 1 == bins ? b : a + (i + 1) * h, tolerance, 8);
  double mass = std::accumulate(probabilities.begin(), probabilities.end(), 0.0);
  std::vector<double> obs = observed, exp(bins);
  for (int i = 0; i < bins; ++i) exp[i] = probabilities[i] * double(totalDraws);
  obs.push_back(double(totalDraws - samples.size()));
  exp.push_back(std::max(0.0, 1.0 - mass) * double(totalDraws));
  Chi2Result r = pearsonChi2(obs, exp, options, [&](size_t i) {
    if (i == size_t(bins)) return std::string("'no sample'");
    return fmt("bin [%.6g, %.6g)", a + i * h, a + (i + 1) * h);
  });
  r.densityMass = mass;
  if (outside > 0) {
    r.passed = false;
    r.report = std::to_string(outside) + " samples outside [a, b]\n" + r.report;
  }
  return r;
}

}  // namespace vktg::test
