// XYZ reader (.xyz/.txt): x y z, x y z nx ny nz, or x y z r g b per line (with a density field,
// a density after them: 4 or 7 columns); a first line holding just the point count is skipped,
// and decimal commas are read as decimal points.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {
namespace {

// Whether `token` is a number written with a decimal comma ("-0,0094"): digits, one comma
// between digits, an optional sign.
bool has_decimal_comma(std::string_view token) {
  if (!token.empty() && (token[0] == '-' || token[0] == '+')) token.remove_prefix(1);
  const std::size_t comma = token.find(',');
  if (comma == std::string_view::npos || comma == 0 || comma + 1 == token.size() ||
      token.find(',', comma + 1) != std::string_view::npos)
    return false;
  return std::all_of(token.begin(), token.end(),
                     [](char c) { return c == ',' || std::isdigit(static_cast<unsigned char>(c)); });
}

// A whole number ("0", "-12"): may stand beside decimal-comma numbers.
bool is_whole_number(std::string_view token) {
  if (!token.empty() && (token[0] == '-' || token[0] == '+')) token.remove_prefix(1);
  return !token.empty() && std::all_of(token.begin(), token.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
}

// A file whose data lines are whitespace-separated numbers, whole or with one decimal comma,
// some with a comma, and no decimal point anywhere ("0,0094 -0,0241 0,9997"); commas are
// otherwise separators.
bool uses_decimal_commas(std::string_view text) {
  if (text.find('.') != std::string_view::npos) return false;
  bool comma_seen = false;
  std::size_t position = 0;
  while (position < text.size()) {
    std::size_t end = text.find('\n', position);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(position, end - position);
    position = end + 1;
    line = line.substr(0, line.find('#'));
    std::vector<std::string_view> words;
    for (std::size_t start = 0; start < line.size();) {
      while (start < line.size() && std::isspace(static_cast<unsigned char>(line[start]))) ++start;
      std::size_t stop = start;
      while (stop < line.size() && !std::isspace(static_cast<unsigned char>(line[stop]))) ++stop;
      if (stop > start) words.push_back(line.substr(start, stop - start));
      start = stop;
    }
    if (words.size() <= 1) continue;  // blank, or a count line
    for (std::string_view word : words) {
      if (has_decimal_comma(word))
        comma_seen = true;
      else if (!is_whole_number(word))
        return false;
    }
  }
  return comma_seen;
}

// Columns 4-6 that are colours, not normals: whole numbers from 0 to 255, some above 1.
bool are_colours(const std::vector<Vec3>& extra) {
  double largest = 0.0;
  for (const Vec3& e : extra)
    for (int c = 0; c < 3 && !std::isnan(e.x()); ++c) {  // NaN: a line of 3 columns
      if (!(e[c] >= 0.0 && e[c] <= 255.0) || e[c] != std::floor(e[c])) return false;
      largest = std::max(largest, e[c]);
    }
  return largest > 1.0;
}

}  // namespace

SurfaceInput parse_xyz(const std::string& path, std::string_view text,
                       const std::string& density_field) {
  std::string converted;
  if (uses_decimal_commas(text)) {
    converted.assign(text);
    std::replace(converted.begin(), converted.end(), ',', '.');
    text = converted;
  }
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  std::vector<Vec3> points, extra;
  std::vector<double> density;
  const std::size_t last = density_field.empty() ? 0 : 1;  // the density's column
  bool first = true;
  std::size_t announced = 0, count_line = 0;
  while (lines.next(tokens)) {
    if (first && tokens.size() == 1) {  // the point count, as some tools write it
      announced = lines.count(tokens[0]);
      count_line = lines.line();
      first = false;
      continue;
    }
    first = false;
    if (tokens.size() != 3 + last && tokens.size() != 6 + last)
      lines.fail(last == 0 ? "expected 3 or 6 columns (x y z [nx ny nz | r g b]), found " +
                                 std::to_string(tokens.size()) +
                                 (tokens.size() == 4 || tokens.size() == 7
                                      ? " (a last column of 4 or 7 is read as a density field)"
                                      : "")
                           : "expected 4 or 7 columns (x y z [nx ny nz | r g b] density), found " +
                                 std::to_string(tokens.size()));
    points.push_back(lines.vec3(tokens, 0));
    if (last) density.push_back(lines.number(tokens.back()));
    if (tokens.size() == 6 + last) {
      extra.resize(points.size(), Vec3::Constant(kNaN));
      extra.back() = lines.vec3(tokens, 3);
    } else if (!extra.empty()) {
      extra.push_back(Vec3::Constant(kNaN));
    }
  }
  if (count_line > 0 && announced != points.size())
    fail(path, "line " + std::to_string(count_line) + " announces " + std::to_string(announced) +
                   " points but " + std::to_string(points.size()) + " follow");
  // The points move into the surface: a big cloud is not held twice.
  SurfaceInput surface;
  if (!extra.empty() && !are_colours(extra)) {
    extra.resize(points.size(), Vec3::Constant(kNaN));
    surface.normals = std::move(extra);
  }
  surface.points = std::move(points);
  surface.density = std::move(density);
  return surface;
}

}  // namespace vmas::io_internal
