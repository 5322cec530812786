#include "scene/mesh_reading.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace vktg {

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  constexpr std::string_view kSpace = " \t\r";
  size_t at = line.find_first_not_of(kSpace);
  while (at != std::string_view::npos) {
    const size_t end = std::min(line.find_first_of(kSpace, at), line.size());
    words.push_back(line.substr(at, end - at));
    at = line.find_first_not_of(kSpace, end);
  }
  return words;
}

namespace {

// std::from_chars takes no leading '+'; the text formats allow one.
std::string_view withoutPlus(std::string_view word) {
  if (word.size() > 1 && word[0] == '+' && word[1] != '-' && word[1] != '+') word.remove_prefix(1);
  return word;
}

// The whole word as a T (std::from_chars, after an optional leading '+'), or nothing.
template <typename T>
std::optional<T> parseWord(std::string_view word) {
  word = withoutPlus(word);
  T value = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc() || end != word.data() + word.size() || word.empty()) return std::nullopt;
  return value;
}

}  // namespace

std::optional<double> parseDecimalWord(std::string_view word) { return parseWord<double>(word); }

std::optional<int64_t> parseIntegerWord(std::string_view word) { return parseWord<int64_t>(word); }

bool finiteAsFloat(double value) { return std::abs(value) <= double(std::numeric_limits<float>::max()); }

void appendFan(std::vector<glm::uvec3>& triangles, const uint32_t* polygon, size_t count) {
  for (size_t k = 1; k + 1 < count; ++k) triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
}

std::string quoteWord(std::string_view word) {
  constexpr size_t kMaxShown = 40;
  std::string out = "\"";
  for (size_t i = 0; i < word.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(word[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += char(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (word.size() > kMaxShown) out += "...";
  return out + "\"";
}

}  // namespace vktg
