// CPU tests of include/vktg/gate.h: the gate spec parser (every form, units, errors), range
// validation, and the gate functions (weight, support, integral, jumps, layer names). The
// integrals are checked against numerical quadrature of weight(), which shares no code with the
// closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <regex>
#include <set>

#include "vktg/error.h"
#include "vktg/gate.h"

namespace vktg {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Composite Simpson of totalWeight over [lo, hi] with the gate's jumps as panel boundaries, so
// the discontinuities never fall inside a panel.
double integrateWeight(const Gate& gate, double lo, double hi) {
  std::vector<double> cuts = {lo, hi};
  for (double j : gate.jumpLocations())
    if (j > lo && j < hi) cuts.push_back(j);
  std::sort(cuts.begin(), cuts.end());
  double total = 0;
  for (size_t p = 0; p + 1 < cuts.size(); ++p) {
    const int n = 20000;
    const double a = cuts[p], h = (cuts[p + 1] - a) / n;
    // Evaluate just inside the panel's ends: weight() at a jump takes one side's value.
    auto f = [&](int i) {
      double x = a + i * h;
      if (i == 0) x += 1e-12 * std::max(1.0, std::abs(x));
      if (i == n) x -= 1e-12 * std::max(1.0, std::abs(x));
      return gate.totalWeight(x);
    };
    double sum = f(0) + f(n);
    for (int i = 1; i < n; ++i) sum += f(i) * (i % 2 ? 4.0 : 2.0);
    total += sum * h / 3.0;
  }
  return total;
}

TEST(GateParse, Steady) {
  Gate g = parseGateSpec("steady");
  EXPECT_EQ(g.type, GateType::Steady);
  EXPECT_EQ(g.layers(), 1u);
}

TEST(GateParse, Gaussian) {
  Gate g = parseGateSpec("gaussian:4.5,0.25");
  EXPECT_EQ(g.type, GateType::Gaussian);
  EXPECT_DOUBLE_EQ(g.mu, 4.5);
  EXPECT_DOUBLE_EQ(g.sigma, 0.25);
  EXPECT_FALSE(g.normalize);
}

TEST(GateParse, Box) {
  Gate g = parseGateSpec("box:3,5.5");
  EXPECT_EQ(g.type, GateType::Box);
  EXPECT_DOUBLE_EQ(g.a, 3.0);
  EXPECT_DOUBLE_EQ(g.b, 5.5);
}

TEST(GateParse, TruncatedGaussian) {
  Gate g = parseGateSpec("tgauss:4,0.5,3.5,5");
  EXPECT_EQ(g.type, GateType::TruncatedGaussian);
  EXPECT_DOUBLE_EQ(g.mu, 4.0);
  EXPECT_DOUBLE_EQ(g.sigma, 0.5);
  EXPECT_DOUBLE_EQ(g.a, 3.5);
  EXPECT_DOUBLE_EQ(g.b, 5.0);
}

TEST(GateParse, Bins) {
  Gate g = parseGateSpec("bins:3,0.25,40");
  EXPECT_EQ(g.type, GateType::Bins);
  EXPECT_DOUBLE_EQ(g.binStart, 3.0);
  EXPECT_DOUBLE_EQ(g.binWidth, 0.25);
  EXPECT_EQ(g.binCount, 40u);
  EXPECT_EQ(g.layers(), 40u);
}

TEST(GateParse, NanosecondSuffixConvertsWithTheSpeedOfLight) {
  // 10 ns of flight is 2.99792458 m of optical path.
  Gate g = parseGateSpec("box:10ns,20ns");
  EXPECT_NEAR(g.a, 2.99792458, 1e-12);
  EXPECT_NEAR(g.b, 5.99584916, 1e-12);
  Gate t = parseGateSpec("gaussian:10ns,0.1ns");
  EXPECT_NEAR(t.mu, 2.99792458, 1e-12);
  EXPECT_NEAR(t.sigma, 0.0299792458, 1e-14);
  Gate b = parseGateSpec("bins:1ns,0.5ns,8");
  EXPECT_NEAR(b.binStart, 0.299792458, 1e-12);
  EXPECT_NEAR(b.binWidth, 0.149896229, 1e-12);
  EXPECT_EQ(b.binCount, 8u);
}

TEST(GateParse, MetreSuffixAndMixedUnits) {
  Gate g = parseGateSpec("box:3m,20ns");
  EXPECT_DOUBLE_EQ(g.a, 3.0);
  EXPECT_NEAR(g.b, 5.99584916, 1e-12);
}

// Every rejected spec throws vktg::Error (not some other exception) and names the field.
void expectRejected(const std::string& spec, const std::string& keyword) {
  SCOPED_TRACE("spec '" + spec + "'");
  try {
    parseGateSpec(spec, "--gate");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("--gate"), std::string::npos) << message;
    EXPECT_NE(message.find(keyword), std::string::npos) << message;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-vktg exception: " << e.what();
  }
}

TEST(GateParse, RejectsUnknownKind) { expectRejected("gauss:4,0.1", "unknown gate"); }
TEST(GateParse, RejectsWrongArgumentCount) {
  expectRejected("box:3", "box:A,B");
  expectRejected("box:3,4,5", "box:A,B");
  expectRejected("gaussian:4", "gaussian:MU,SIGMA");
  expectRejected("tgauss:4,0.5,3", "tgauss:MU,SIGMA,A,B");
  expectRejected("bins:3,0.5", "bins:START,WIDTH,COUNT");
  expectRejected("steady:1", "steady");
}
TEST(GateParse, RejectsNonNumbers) {
  expectRejected("box:x,5", "not a number");
  expectRejected("box:3,5q", "not a number");
  expectRejected("box:,5", "not a number");
  expectRejected("box:3,5nsx", "not a number");
}
TEST(GateParse, RejectsNonFiniteNumbers) {
  expectRejected("gaussian:nan,0.1", "finite");
  expectRejected("gaussian:4,inf", "finite");
  expectRejected("box:3,1e999", "1e999");
}
TEST(GateParse, RejectsBadBinCounts) {
  expectRejected("bins:3,0.5,0", "count");
  expectRejected("bins:3,0.5,2.5", "count");
  expectRejected("bins:3,0.5,100000", "count");
}
TEST(GateParse, RejectsNonNumericBinCounts) {
  expectRejected("bins:3,0.5,many", "count");
  expectRejected("bins:3,0.5,4x", "count");
}

TEST(GateValidate, Ranges) {
  expectRejected("gaussian:4,0", "sigma must be > 0");
  expectRejected("gaussian:4,-0.1", "sigma must be > 0");
  expectRejected("gaussian:-1,0.1", "mu must be >= 0");
  expectRejected("box:5,3", "a must be < b");
  expectRejected("box:3,3", "a must be < b");
  expectRejected("box:-1,3", "a must be >= 0");
  expectRejected("tgauss:4,0.5,5,3", "a must be < b");
  expectRejected("tgauss:4,0,3,5", "sigma must be > 0");
  expectRejected("bins:-1,0.5,4", "start must be >= 0");
  expectRejected("bins:3,0,4", "width must be > 0");
}

TEST(GateValidate, NamesFileAndField) {
  Gate g;
  g.type = GateType::Box;
  g.a = 5;
  g.b = 3;
  try {
    validateGate(g, "room.json", "gate");
    ADD_FAILURE() << "accepted a > b";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "room.json: gate: a must be < b");
  }
  g.b = 6;
  EXPECT_NO_THROW(validateGate(g, "room.json", "gate"));
}

TEST(GateWeight, Steady) {
  Gate g = parseGateSpec("steady");
  for (double L : {0.0, 1.0, 1e6}) EXPECT_EQ(g.weight(L), 1.0);
  EXPECT_EQ(g.supportMin(), 0.0);
  EXPECT_EQ(g.supportMax(), kInf);
  EXPECT_EQ(g.integral(), kInf);
  EXPECT_EQ(g.width(), kInf);
  EXPECT_FALSE(g.hasJumps());
  EXPECT_TRUE(g.jumpLocations().empty());
}

TEST(GateWeight, GaussianValuesCutoffAndNormalisation) {
  Gate g = parseGateSpec("gaussian:4,0.5");
  EXPECT_DOUBLE_EQ(g.weight(4.0), 1.0);
  EXPECT_NEAR(g.weight(4.5), std::exp(-0.5), 1e-15);
  EXPECT_NEAR(g.weight(3.0), std::exp(-2.0), 1e-15);
  const double edge = kGaussianCutoff * 0.5;
  EXPECT_GT(g.weight(4.0 + edge * 0.999), 0.0);
  EXPECT_EQ(g.weight(4.0 + edge * 1.001), 0.0);
  EXPECT_EQ(g.weight(4.0 - edge * 1.001), 0.0);
  EXPECT_DOUBLE_EQ(g.supportMin(), 4.0 - edge);
  EXPECT_DOUBLE_EQ(g.supportMax(), 4.0 + edge);
  EXPECT_FALSE(g.hasJumps());
  EXPECT_DOUBLE_EQ(g.width(), 0.5);
  g.normalize = true;
  EXPECT_NEAR(g.weight(4.0), 1.0 / (0.5 * std::sqrt(2 * std::numbers::pi)), 1e-15);
}

TEST(GateWeight, BoxIsClosed) {
  Gate g = parseGateSpec("box:3,5");
  EXPECT_EQ(g.weight(3.0), 1.0);
  EXPECT_EQ(g.weight(5.0), 1.0);
  EXPECT_EQ(g.weight(4.0), 1.0);
  EXPECT_EQ(g.weight(std::nextafter(3.0, 0.0)), 0.0);
  EXPECT_EQ(g.weight(std::nextafter(5.0, 9.0)), 0.0);
  EXPECT_EQ(g.supportMin(), 3.0);
  EXPECT_EQ(g.supportMax(), 5.0);
  EXPECT_EQ(g.jumpLocations(), (std::vector<double>{3.0, 5.0}));
  EXPECT_TRUE(g.hasJumps());
  EXPECT_EQ(g.width(), 2.0);
}

TEST(GateWeight, TruncatedGaussian) {
  Gate g = parseGateSpec("tgauss:4,0.5,3.5,5");
  EXPECT_NEAR(g.weight(3.5), std::exp(-0.5), 1e-15);
  EXPECT_NEAR(g.weight(5.0), std::exp(-2.0), 1e-15);
  EXPECT_EQ(g.weight(std::nextafter(3.5, 0.0)), 0.0);
  EXPECT_EQ(g.weight(std::nextafter(5.0, 9.0)), 0.0);
  EXPECT_EQ(g.jumpLocations(), (std::vector<double>{3.5, 5.0}));
  EXPECT_TRUE(g.hasJumps());
  EXPECT_DOUBLE_EQ(g.width(), 0.5);
}

TEST(GateWeight, BinsAreHalfOpenAndTileTheirRange) {
  Gate g = parseGateSpec("bins:3,0.5,4");
  // Each length inside [3, 5) lies in exactly one bin; the bin edge belongs to the upper bin.
  for (double L = 2.75; L <= 5.25; L += 0.03125) {
    double sum = 0;
    for (uint32_t k = 0; k < 4; ++k) sum += g.weight(L, k);
    EXPECT_EQ(sum, (L >= 3.0 && L < 5.0) ? 1.0 : 0.0) << "L = " << L;
    EXPECT_EQ(g.totalWeight(L), sum) << "L = " << L;
  }
  EXPECT_EQ(g.weight(3.5, 0), 0.0);
  EXPECT_EQ(g.weight(3.5, 1), 1.0);
  EXPECT_EQ(g.supportMin(), 3.0);
  EXPECT_EQ(g.supportMax(), 5.0);
  EXPECT_EQ(g.jumpLocations(), (std::vector<double>{3.0, 3.5, 4.0, 4.5, 5.0}));
  EXPECT_EQ(g.width(), 0.5);
}

TEST(GateWeight, ZeroOutsideSupportForPathLengths) {
  // The contract the renderer relies on to end paths early (lengths are never negative).
  for (const char* spec : {"gaussian:4,0.5", "gaussian:0.5,0.25", "box:3,5", "tgauss:4,0.5,3.5,5", "bins:3,0.5,4"}) {
    Gate g = parseGateSpec(spec);
    for (double L = 0; L < 10; L += 0.001) {
      if (L >= g.supportMin() && L <= g.supportMax()) continue;
      ASSERT_EQ(g.totalWeight(L), 0.0) << spec << " at L = " << L;
    }
  }
}

TEST(GateIntegral, MatchesQuadratureOfTheWeight) {
  for (const char* spec : {"gaussian:4,0.5", "gaussian:0.5,0.25", "box:3,5", "tgauss:4,0.5,3.5,5", "tgauss:4,0.5,2,9",
                           "bins:3,0.5,4"}) {
    for (bool normalize : {false, true}) {
      Gate g = parseGateSpec(spec);
      if (normalize && g.type != GateType::Gaussian) continue;
      g.normalize = normalize;
      SCOPED_TRACE(std::string(spec) + (normalize ? " normalised" : ""));
      // Over all path lengths: [0, supportMax] (a path length is never negative).
      double quadrature = integrateWeight(g, 0.0, g.supportMax());
      EXPECT_NEAR(g.integral(), quadrature, 1e-9 * std::max(1.0, quadrature));
    }
  }
  // Closed forms that need no quadrature.
  EXPECT_DOUBLE_EQ(parseGateSpec("box:3,5").integral(), 2.0);
  EXPECT_DOUBLE_EQ(parseGateSpec("bins:3,0.5,4").integral(), 2.0);
  Gate unit = parseGateSpec("gaussian:4,0.5");
  unit.normalize = true;
  EXPECT_NEAR(unit.integral(), 1.0, 1e-9);  // the 6.5 sigma cutoff loses 8e-11
}

TEST(GateLayers, NamesCarryIndexAndRangeAndSortInOrder) {
  Gate g = parseGateSpec("bins:3,0.25,12");
  std::set<std::string> names;
  std::string previous;
  for (uint32_t k = 0; k < 12; ++k) {
    std::string name = g.layerName(k);
    std::smatch m;
    ASSERT_TRUE(std::regex_match(name, m, std::regex("bin_0*([0-9]+)_([0-9.]+)-([0-9.]+)"))) << name;
    EXPECT_EQ(std::stoul(m[1]), k) << name;
    EXPECT_NEAR(std::stod(m[2]), 3.0 + 0.25 * k, 1e-9) << name;
    EXPECT_NEAR(std::stod(m[3]), 3.25 + 0.25 * k, 1e-9) << name;
    // EXR readers list layers by name: zero-padded indices keep them in bin order.
    EXPECT_LT(previous, name);
    previous = name;
    names.insert(name);
  }
  EXPECT_EQ(names.size(), 12u);
  EXPECT_EQ(parseGateSpec("box:3,5").layerName(0), "");
}

TEST(GateDescribe, SaysTypeAndNumbers) {
  EXPECT_EQ(parseGateSpec("steady").describe(), "steady");
  EXPECT_NE(parseGateSpec("box:3,5").describe().find("box"), std::string::npos);
  EXPECT_NE(parseGateSpec("bins:3,0.5,4").describe().find("4 bins"), std::string::npos);
  EXPECT_NE(parseGateSpec("gaussian:4,0.5").describe().find("sigma 0.5"), std::string::npos);
}

}  // namespace
}  // namespace vktg
