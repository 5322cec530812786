// Time gates W(L): path-length importance functions. L is optical path length in scene units
// (metres); specs with an `ns` suffix are converted with c. See THEORY.md §1.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace vktg {

inline constexpr double kSpeedOfLight = 0.299792458;  // metres per nanosecond

enum class GateType : uint32_t { Steady = 0, Gaussian = 1, Box = 2, TruncatedGaussian = 3, Bins = 4 };

struct Gate {
  GateType type = GateType::Steady;
  double mu = 0, sigma = 0;          // gaussian, truncated gaussian
  double a = 0, b = 0;               // box, truncated gaussian: support [a, b]
  bool normalize = false;            // gaussian: divide by sigma*sqrt(2*pi)
  double binStart = 0, binWidth = 0; // bins: box gates [start + k*width, start + (k+1)*width)
  uint32_t binCount = 1;

  uint32_t layers() const { return type == GateType::Bins ? binCount : 1; }
  // W_k(L) for layer k (k = 0 unless bins).
  double weight(double length, uint32_t layer = 0) const;
  // The same gate moved towards longer paths by `delta` metres: W'(L) = W(L - delta) (gate_center).
  Gate shifted(double delta) const;
  // Sum over layers of W_k(L): the density gate sampling draws from.
  double totalWeight(double length) const;
  // Lengths outside [supportMin, supportMax] have W = 0 (gaussians: |L - mu| > kGaussianCutoff sigma).
  double supportMin() const;
  double supportMax() const;
  // Integral of totalWeight over L (infinite for steady).
  double integral() const;
  // Width of the gate in length units (for the planner): sigma, b - a, bin width; infinity for steady.
  double width() const;
  bool hasJumps() const;                  // box, truncated gaussian, bins
  std::vector<double> jumpLocations() const;
  std::string describe() const;           // e.g. "box [3 m, 5 m]"
  std::string layerName(uint32_t layer) const;  // EXR layer name, e.g. "bin_012_3.000-3.100"
  bool operator==(const Gate&) const = default;
};

inline constexpr double kGaussianCutoff = 6.5;  // W < 7e-10 beyond 6.5 sigma

// Parses `gaussian:MU,SIGMA`, `box:A,B`, `tgauss:MU,SIGMA,A,B`, `steady`, `bins:START,WIDTH,COUNT`;
// numbers may carry an `ns` suffix. Throws vktg::Error naming `field` on bad input.
Gate parseGateSpec(const std::string& spec, const std::string& field = "--gate");
// Checks ranges (finite, sigma > 0, a < b, ...). Throws vktg::Error with file/field.
void validateGate(const Gate& gate, const std::string& file, const std::string& field);

}  // namespace vktg
