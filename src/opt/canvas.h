// A small 8-bit RGB raster for the figures of src/opt/plot.cpp: filled rectangles, thick lines,
// text in stb_easy_font's built-in font (ASCII; other characters are drawn as '?'), PNG output.
// Coordinates are pixels, x to the right and y down from the top-left corner; everything drawn
// outside the canvas is clipped.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vktg {

using Rgb = std::array<uint8_t, 3>;

class Canvas {
 public:
  Canvas(uint32_t width, uint32_t height, Rgb background);

  uint32_t width() const { return m_width; }
  uint32_t height() const { return m_height; }
  Rgb at(int x, int y) const;  // the canvas must contain (x, y)

  void set(int x, int y, Rgb colour);
  void fillRect(int x0, int y0, int x1, int y1, Rgb colour);  // [x0, x1) x [y0, y1)
  // A line between pixel centres, `thickness` pixels wide (a square brush centred on the line).
  void line(int x0, int y0, int x1, int y1, Rgb colour, int thickness);
  // Text whose top-left corner is (x, y), each font pixel `scale` x `scale` pixels. Vertical text
  // reads from bottom to top (turned 90 degrees counter-clockwise); (x, y) is still the top-left
  // corner of the box it fills, textHeight wide and textWidth tall.
  void text(int x, int y, const std::string& text, Rgb colour, int scale, bool vertical = false);
  static int textWidth(const std::string& text, int scale);
  static int textHeight(int scale);  // one line, including room for descenders

  // Encodes the canvas as PNG and writes it atomically.
  void writePng(const std::filesystem::path& path) const;

 private:
  uint32_t m_width, m_height;
  std::vector<uint8_t> m_pixels;  // RGB, rows top to bottom
};

}  // namespace vktg
