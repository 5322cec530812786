#include "vktg/gate.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "vktg/error.h"

namespace vktg {
namespace {

constexpr double kSqrt2Pi = 2.50662827463100050242;

double gaussian(double length, double mu, double sigma) {
  double z = (length - mu) / sigma;
  return std::exp(-0.5 * z * z);
}

std::vector<std::string> splitCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) parts.push_back(item);
  return parts;
}

// A length in metres, or nanoseconds with an `ns` suffix (converted with c).
double parseLength(const std::string& text, const std::string& field) {
  std::string body = text;
  double scale = 1.0;
  if (body.size() > 2 && body.compare(body.size() - 2, 2, "ns") == 0) {
    body.resize(body.size() - 2);
    scale = kSpeedOfLight;
  } else if (body.size() > 1 && body.back() == 'm') {
    body.pop_back();
  }
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(body, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != body.size()) fail("", field, "'" + text + "' is not a number (metres, or nanoseconds with 'ns')");
  return value * scale;
}

}  // namespace

Gate Gate::shifted(double delta) const {
  Gate g = *this;
  switch (type) {
    case GateType::Steady: break;
    case GateType::Gaussian: g.mu += delta; break;
    case GateType::TruncatedGaussian: g.mu += delta; [[fallthrough]];
    case GateType::Box:
      g.a += delta;
      g.b += delta;
      break;
    case GateType::Bins: g.binStart += delta; break;
  }
  return g;
}

double Gate::weight(double length, uint32_t layer) const {
  switch (type) {
    case GateType::Steady: return 1.0;
    case GateType::Gaussian: {
      if (std::abs(length - mu) > kGaussianCutoff * sigma) return 0.0;
      double w = gaussian(length, mu, sigma);
      return normalize ? w / (sigma * kSqrt2Pi) : w;
    }
    case GateType::Box: return (length >= a && length <= b) ? 1.0 : 0.0;
    case GateType::TruncatedGaussian: return (length >= a && length <= b) ? gaussian(length, mu, sigma) : 0.0;
    case GateType::Bins: {
      double lo = binStart + binWidth * layer;
      return (length >= lo && length < lo + binWidth) ? 1.0 : 0.0;
    }
  }
  return 0.0;
}

double Gate::totalWeight(double length) const {
  if (type != GateType::Bins) return weight(length, 0);
  return (length >= supportMin() && length < supportMax()) ? 1.0 : 0.0;
}

double Gate::supportMin() const {
  switch (type) {
    case GateType::Steady: return 0.0;
    case GateType::Gaussian: return std::max(0.0, mu - kGaussianCutoff * sigma);
    case GateType::Box:
    case GateType::TruncatedGaussian: return a;
    case GateType::Bins: return binStart;
  }
  return 0.0;
}

double Gate::supportMax() const {
  switch (type) {
    case GateType::Steady: return std::numeric_limits<double>::infinity();
    case GateType::Gaussian: return mu + kGaussianCutoff * sigma;
    case GateType::Box:
    case GateType::TruncatedGaussian: return b;
    case GateType::Bins: return binStart + binWidth * binCount;
  }
  return 0.0;
}

double Gate::integral() const {
  switch (type) {
    case GateType::Steady: return std::numeric_limits<double>::infinity();
    case GateType::Gaussian: {
      // Truncated at the cutoff like weight(); also at L = 0 when mu is close to 0.
      double lo = supportMin(), hi = supportMax();
      double s2 = sigma * std::sqrt(2.0);
      double mass = 0.5 * (std::erf((hi - mu) / s2) - std::erf((lo - mu) / s2));
      return normalize ? mass : mass * sigma * kSqrt2Pi;
    }
    case GateType::Box: return b - a;
    case GateType::TruncatedGaussian: {
      double s2 = sigma * std::sqrt(2.0);
      return 0.5 * sigma * kSqrt2Pi * (std::erf((b - mu) / s2) - std::erf((a - mu) / s2));
    }
    case GateType::Bins: return binWidth * binCount;
  }
  return 0.0;
}

double Gate::width() const {
  switch (type) {
    case GateType::Steady: return std::numeric_limits<double>::infinity();
    case GateType::Gaussian: return sigma;
    case GateType::Box: return b - a;
    case GateType::TruncatedGaussian: return std::min(sigma, b - a);
    case GateType::Bins: return binWidth;
  }
  return 0.0;
}

bool Gate::hasJumps() const {
  return type == GateType::Box || type == GateType::TruncatedGaussian || type == GateType::Bins;
}

std::vector<double> Gate::jumpLocations() const {
  switch (type) {
    case GateType::Box:
    case GateType::TruncatedGaussian: return {a, b};
    case GateType::Bins: {
      std::vector<double> edges;
      for (uint32_t k = 0; k <= binCount; ++k) edges.push_back(binStart + binWidth * k);
      return edges;
    }
    default: return {};
  }
}

std::string Gate::describe() const {
  char text[160];
  switch (type) {
    case GateType::Steady: return "steady";
    case GateType::Gaussian:
      std::snprintf(text, sizeof text, "gaussian mu %.6g m, sigma %.6g m (sigma/mu %.2g)", mu, sigma, sigma / mu);
      return text;
    case GateType::Box: std::snprintf(text, sizeof text, "box [%.6g m, %.6g m]", a, b); return text;
    case GateType::TruncatedGaussian:
      std::snprintf(text, sizeof text, "truncated gaussian mu %.6g m, sigma %.6g m on [%.6g m, %.6g m]", mu, sigma, a, b);
      return text;
    case GateType::Bins:
      std::snprintf(text, sizeof text, "%u bins of %.6g m from %.6g m", binCount, binWidth, binStart);
      return text;
  }
  return "";
}

std::string Gate::layerName(uint32_t layer) const {
  if (type != GateType::Bins) return "";
  char text[96];
  double lo = binStart + binWidth * layer;
  std::snprintf(text, sizeof text, "bin_%04u_%.4f-%.4f", layer, lo, lo + binWidth);
  return text;
}

Gate parseGateSpec(const std::string& spec, const std::string& field) {
  Gate gate;
  size_t colon = spec.find(':');
  std::string kind = spec.substr(0, colon);
  std::vector<std::string> args = colon == std::string::npos ? std::vector<std::string>{} : splitCommas(spec.substr(colon + 1));
  auto expect = [&](size_t count, const char* usage) {
    if (args.size() != count) fail("", field, "'" + spec + "': expected " + usage);
  };
  auto number = [&](size_t i) { return parseLength(args[i], field); };
  if (kind == "steady") {
    expect(0, "steady");
  } else if (kind == "gaussian") {
    expect(2, "gaussian:MU,SIGMA");
    gate.type = GateType::Gaussian;
    gate.mu = number(0);
    gate.sigma = number(1);
  } else if (kind == "box") {
    expect(2, "box:A,B");
    gate.type = GateType::Box;
    gate.a = number(0);
    gate.b = number(1);
  } else if (kind == "tgauss") {
    expect(4, "tgauss:MU,SIGMA,A,B");
    gate.type = GateType::TruncatedGaussian;
    gate.mu = number(0);
    gate.sigma = number(1);
    gate.a = number(2);
    gate.b = number(3);
  } else if (kind == "bins") {
    expect(3, "bins:START,WIDTH,COUNT");
    gate.type = GateType::Bins;
    gate.binStart = number(0);
    gate.binWidth = number(1);
    size_t used = 0;
    double count = 0;
    try {
      count = std::stod(args[2], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != args[2].size() || !(count >= 1 && count <= 65536 && count == std::floor(count)))
      fail("", field, "'" + spec + "': bin count must be an integer in [1, 65536]");
    gate.binCount = static_cast<uint32_t>(count);
  } else {
    fail("", field, "unknown gate '" + kind + "' (expected gaussian, box, tgauss, steady or bins)");
  }
  validateGate(gate, "", field);
  return gate;
}

void validateGate(const Gate& gate, const std::string& file, const std::string& field) {
  auto finite = [&](double v, const char* name) {
    if (!std::isfinite(v)) fail(file, field, std::string(name) + " must be a finite number");
  };
  switch (gate.type) {
    case GateType::Steady: return;
    case GateType::Gaussian:
    case GateType::TruncatedGaussian:
      finite(gate.mu, "mu");
      finite(gate.sigma, "sigma");
      if (gate.sigma <= 0) fail(file, field, "sigma must be > 0");
      if (gate.mu < 0) fail(file, field, "mu must be >= 0 (a path length)");
      if (gate.type == GateType::Gaussian) return;
      [[fallthrough]];
    case GateType::Box:
      finite(gate.a, "a");
      finite(gate.b, "b");
      if (gate.a < 0) fail(file, field, "a must be >= 0 (a path length)");
      if (!(gate.a < gate.b)) fail(file, field, "a must be < b");
      return;
    case GateType::Bins:
      finite(gate.binStart, "start");
      finite(gate.binWidth, "width");
      if (gate.binStart < 0) fail(file, field, "start must be >= 0");
      if (gate.binWidth <= 0) fail(file, field, "width must be > 0");
      if (gate.binCount < 1) fail(file, field, "count must be >= 1");
      return;
  }
}

}  // namespace vktg
