// The raster behind the run's figures (canvas.h). Text comes from stb_easy_font, which builds each
// glyph from axis-aligned quads: drawing text is filling those rectangles, scaled.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

#include "opt/canvas.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg {
namespace {

constexpr int kLineAdvance = 12;  // stb_easy_font's line height in font pixels
constexpr size_t kVertexBytes = 16;  // x, y, z floats and 4 colour bytes
constexpr size_t kMaxQuadsPerGlyph = 32;

// stb_easy_font indexes a table by (character - 32) and knows only printable ASCII: anything else
// becomes '?' (one per UTF-8 sequence), control characters become spaces.
std::string printable(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (c >= 0x80) {
      if (c >= 0xc0) out += '?';  // a UTF-8 lead byte; continuation bytes (0x80-0xbf) are dropped
    } else {
      out += (c < 32 || c == 127) ? ' ' : char(c);
    }
  }
  return out;
}

struct Quad {
  float x0, y0, x1, y1;
};

std::vector<Quad> glyphQuads(const std::string& text) {
  std::string chars = printable(text);
  // stb_easy_font silently drops quads that do not fit; no glyph has more than kMaxQuadsPerGlyph.
  std::vector<char> buffer((chars.size() + 1) * kMaxQuadsPerGlyph * 4 * kVertexBytes);
  const int count = stb_easy_font_print(0, 0, chars.data(), nullptr, buffer.data(), int(buffer.size()));
  std::vector<Quad> quads(size_t(std::max(count, 0)));
  for (size_t q = 0; q < quads.size(); ++q) {
    float first[2], third[2];  // vertices 0 and 2 are opposite corners
    std::memcpy(first, buffer.data() + (4 * q) * kVertexBytes, sizeof first);
    std::memcpy(third, buffer.data() + (4 * q + 2) * kVertexBytes, sizeof third);
    quads[q] = {first[0], first[1], third[0], third[1]};
  }
  return quads;
}

}  // namespace

Canvas::Canvas(uint32_t width, uint32_t height, Rgb background)
    : m_width(width), m_height(height), m_pixels(size_t(width) * height * 3) {
  for (size_t i = 0; i < m_pixels.size(); i += 3) std::copy(background.begin(), background.end(), m_pixels.begin() + std::ptrdiff_t(i));
}

Rgb Canvas::at(int x, int y) const {
  const size_t i = (size_t(y) * m_width + size_t(x)) * 3;
  return {m_pixels.at(i), m_pixels.at(i + 1), m_pixels.at(i + 2)};
}

void Canvas::set(int x, int y, Rgb colour) {
  if (x < 0 || y < 0 || x >= int(m_width) || y >= int(m_height)) return;
  std::copy(colour.begin(), colour.end(), m_pixels.begin() + std::ptrdiff_t((size_t(y) * m_width + size_t(x)) * 3));
}

void Canvas::fillRect(int x0, int y0, int x1, int y1, Rgb colour) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, int(m_width));
  y1 = std::min(y1, int(m_height));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) set(x, y, colour);
}

void Canvas::line(int x0, int y0, int x1, int y1, Rgb colour, int thickness) {
  const int before = (thickness - 1) / 2, after = thickness / 2;
  // Bresenham: every step moves one pixel along the major axis.
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int error = dx + dy;
  for (;;) {
    fillRect(x0 - before, y0 - before, x0 + after + 1, y0 + after + 1, colour);
    if (x0 == x1 && y0 == y1) return;
    const int twice = 2 * error;
    if (twice >= dy) {
      error += dy;
      x0 += sx;
    }
    if (twice <= dx) {
      error += dx;
      y0 += sy;
    }
  }
}

void Canvas::text(int x, int y, const std::string& text, Rgb colour, int scale, bool vertical) {
  const int width = textWidth(text, scale);
  for (const Quad& q : glyphQuads(text)) {
    const int qx0 = int(q.x0) * scale, qy0 = int(q.y0) * scale, qx1 = int(q.x1) * scale, qy1 = int(q.y1) * scale;
    if (vertical)  // (u, v) -> (v, width - u): a quarter turn counter-clockwise
      fillRect(x + qy0, y + width - qx1, x + qy1, y + width - qx0, colour);
    else
      fillRect(x + qx0, y + qy0, x + qx1, y + qy1, colour);
  }
}

int Canvas::textWidth(const std::string& text, int scale) {
  std::string chars = printable(text);
  return stb_easy_font_width(chars.data()) * scale;
}

int Canvas::textHeight(int scale) { return kLineAdvance * scale; }

void Canvas::writePng(const std::filesystem::path& path) const {
  writeFileAtomic(path, io::encodePng(path, m_width, m_height, 3, m_pixels));
}

}  // namespace vktg
