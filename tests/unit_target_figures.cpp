// Which figures `vktg optimize` draws of its targets (src/opt/target_figures.h): image strips for
// images, curves for a point sensor's transient, one scan figure per gate that several transient
// targets share, and no per-point curves for scans of more than kMaxTransientPlots points.
#include <filesystem>

#include <gtest/gtest.h>

#include "opt/target_figures.h"
#include "support/file_test.h"
#include "support/png_decode.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;
using test::expectError;

ImageSet image(uint32_t width, uint32_t height, std::vector<float> layerValues) {
  ImageSet out{width, height, {}};
  for (float v : layerValues) out.layers.push_back({"", std::vector<float>(size_t(width) * height, v)});
  return out;
}

Gate bins(double start) {
  Gate gate;
  gate.type = GateType::Bins;
  gate.binStart = start;
  gate.binWidth = 0.1;
  gate.binCount = 3;
  return gate;
}

class TargetFigures : public test::TempDirTest {
 protected:
  // n targets named prefix0.. with `gate`, all showing the same three images.
  void add(const std::string& prefix, size_t n, const Gate& gate, const ImageSet& shown) {
    for (size_t i = 0; i < n; ++i) m_targets.push_back({prefix + std::to_string(i), gate, &shown, &shown, &shown});
  }
  std::vector<TargetImages> m_targets;
};

TEST_F(TargetFigures, TransientsGetCurvesAndAScanImagesAStrip) {
  const ImageSet transient = image(1, 1, {0.1f, 0.5f, 0.2f}), picture = image(8, 6, {0.3f});
  add("point", 3, bins(1.0), transient);
  add("camera", 1, Gate{}, picture);
  writeTargetFigures(m_dir, 7, m_targets);
  for (const char* name : {"point0_7.png", "point1_7.png", "point2_7.png"}) {
    const test::DecodedPng png = test::decodePng(m_dir / name);
    EXPECT_EQ(png.width, 640) << name << ": a line plot";
    EXPECT_EQ(png.height, 400);
  }
  EXPECT_TRUE(fs::exists(m_dir / "camera0_7.png"));
  EXPECT_TRUE(fs::exists(m_dir / "transients" / "7.png"));
  EXPECT_FALSE(fs::exists(m_dir / "transients" / "7_1.png"));
}

TEST_F(TargetFigures, LargeScansGetTheScanFigureOnly) {
  const ImageSet transient = image(1, 1, {0.1f, 0.5f, 0.2f});
  add("point", kMaxTransientPlots + 1, bins(1.0), transient);
  writeTargetFigures(m_dir, 0, m_targets);
  EXPECT_TRUE(fs::exists(m_dir / "transients" / "0.png"));
  EXPECT_FALSE(fs::exists(m_dir / "point0_0.png"));
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(m_dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 0u);
}

TEST_F(TargetFigures, OneScanFigurePerSharedGate) {
  const ImageSet transient = image(1, 1, {0.1f, 0.5f, 0.2f});
  add("a", 1, bins(3.0), transient);  // alone with its gate: curves only
  add("b", 2, bins(1.0), transient);
  add("c", 2, bins(2.0), transient);
  writeTargetFigures(m_dir, 4, m_targets);
  EXPECT_TRUE(fs::exists(m_dir / "transients" / "4.png"));
  EXPECT_TRUE(fs::exists(m_dir / "transients" / "4_1.png"));
  EXPECT_FALSE(fs::exists(m_dir / "transients" / "4_2.png"));
  for (const char* name : {"a0_4.png", "b0_4.png", "b1_4.png", "c0_4.png", "c1_4.png"}) EXPECT_TRUE(fs::exists(m_dir / name)) << name;
}

TEST_F(TargetFigures, ImagesThatDisagreeAreErrors) {
  const ImageSet transient = image(1, 1, {0.1f, 0.5f, 0.2f}), shorter = image(1, 1, {0.1f, 0.5f});
  add("point", 2, bins(1.0), transient);
  m_targets[1].current = &shorter;
  expectError([&] { writeTargetFigures(m_dir, 3, m_targets); },
              {(m_dir / "point1_3.png").string(), "iteration 3", "3 bins", "2 layers"});
  // In a scan of more points than get curves, the scan figure finds it.
  m_targets[1].current = &transient;
  m_targets.resize(kMaxTransientPlots + 1, m_targets[0]);
  m_targets.back().name = "last";
  m_targets.back().current = &shorter;
  expectError([&] { writeTargetFigures(m_dir, 3, m_targets); },
              {(m_dir / "transients" / "3.png").string(), "last iteration 3", "2 layers"});
}

}  // namespace
}  // namespace vktg
