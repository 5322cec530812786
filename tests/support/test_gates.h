// The gates the gate tests run over: one of each kind, with dyadic numbers so a kernel's float
// gate equals the CPU's double one.
#pragma once
#include <ostream>
#include <vector>

#include "vktg/gate.h"
#include "vktg/scene.h"

namespace vktg::test {

struct GateCase {
  const char* name;
  Gate gate;
};
// Test names print the case's name rather than its bytes.
inline void PrintTo(const GateCase& c, std::ostream* os) { *os << c.name; }

// A gaussian gate W(L) = exp(-(L - mu)^2 / (2 sigma^2)) (divided by sigma sqrt(2 pi) if normalized).
Gate gaussianGate(double mu, double sigma, bool normalize = false);
// gaussian, gaussian_normalised, box, truncated_gaussian, bins.
std::vector<GateCase> representativeGates();
// The smallest scene that carries `gate` to the GPU (uploading needs one shape and one emitter).
Scene sceneWithGate(const Gate& gate);

}  // namespace vktg::test
