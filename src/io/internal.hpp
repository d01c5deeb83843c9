#pragma once
// Helpers shared by the IO stage's files: the dispatcher (io/read.cpp), one reader per format
// (io/FORMAT.cpp) and the writers (io/write.cpp).
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "vmas/error.hpp"
#include "vmas/io.hpp"
#include "vmas/types.hpp"

// Hidden: internal to the library, never exported (src/exports.map exports the vmas API).
namespace vmas {
namespace io_internal __attribute__((visibility("hidden"))) {

[[noreturn]] inline void fail(const std::string& path, const std::string& problem) {
  throw IoError(path + ": " + problem);
}

// Quotes a token for an error message, keeping the message short and on one printable line.
inline std::string quote(std::string_view token) {
  std::string text(token.substr(0, 40));
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + text + (token.size() > 40 ? "...'" : "'");
}

inline std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// What a path that is not a regular file is, for messages: "a FIFO", "a device", ...
inline std::string file_kind(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::fifo: return "a FIFO";
    case std::filesystem::file_type::block:
    case std::filesystem::file_type::character: return "a device";
    case std::filesystem::file_type::socket: return "a socket";
    case std::filesystem::file_type::directory: return "a directory";
    case std::filesystem::file_type::symlink: return "a symbolic link";
    default: return "not a regular file";
  }
}

inline bool host_is_little_endian() {
  const std::uint16_t probe = 1;
  char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

using Face = std::array<int, 3>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\v' || c == '\f';
}

inline std::string_view trim(std::string_view text) {
  while (!text.empty() && is_separator(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_separator(text.back())) text.remove_suffix(1);
  return text;
}

// The one tokenizer of every text format: yields the tokens (separated by whitespace or commas)
// of each line holding any, skips '#' comments, and knows the line number for error messages.
class LineTokenizer {
 public:
  LineTokenizer(const std::string& path, std::string_view text, std::size_t lines_before = 0)
      : path_(path), text_(text), line_(lines_before) {}

  bool next(std::vector<std::string_view>& tokens) {
    while (position_ < text_.size()) {
      std::size_t end = text_.find('\n', position_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(position_, end - position_);
      position_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      tokens.clear();
      std::size_t start = 0;
      while (start < line.size()) {
        while (start < line.size() && is_separator(line[start])) ++start;
        std::size_t stop = start;
        while (stop < line.size() && !is_separator(line[stop])) ++stop;
        if (stop > start) tokens.push_back(line.substr(start, stop - start));
        start = stop;
      }
      if (!tokens.empty()) return true;
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& problem) const {
    io_internal::fail(path_, "line " + std::to_string(line_) + ": " + problem);
  }

  // Where the text after the last line read starts, and that line's number.
  std::size_t position() const { return std::min(position_, text_.size()); }
  std::size_t line() const { return line_; }

  double number(std::string_view token) const { return parse<double>(token); }
  long long integer(std::string_view token) const { return parse<long long>(token); }

  // A count or size: a non-negative integer.
  std::size_t count(std::string_view token) const {
    const long long value = integer(token);
    if (value < 0) fail("negative count " + quote(token));
    return static_cast<std::size_t>(value);
  }

  Vec3 vec3(const std::vector<std::string_view>& tokens, std::size_t first) const {
    return Vec3(number(tokens[first]), number(tokens[first + 1]), number(tokens[first + 2]));
  }

 private:
  template <typename T>
  T parse(std::string_view token) const {
    std::string_view digits = token;
    if (digits.size() > 1 && digits.front() == '+')
      digits.remove_prefix(1);  // from_chars rejects '+'
    T value{};
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error == std::errc::result_out_of_range) fail("number out of range " + quote(token));
    if (error != std::errc() || end != digits.data() + digits.size())
      fail(std::string(std::is_integral_v<T> ? "expected an integer, found "
                                             : "non-numeric token ") +
           quote(token));
    return value;
  }

  const std::string& path_;
  std::string_view text_;
  std::size_t position_ = 0;
  std::size_t line_;
};

// Converts a stored index to int if it is an integer in [0, count) that an int holds (a header
// may announce more elements than an int can index).
inline bool to_index(double value, std::size_t count, int& index) {
  const double end =
      static_cast<double>(std::min<std::size_t>(count, std::numeric_limits<int>::max()));
  if (!(value >= 0.0 && value < end) || value != std::floor(value)) return false;
  index = static_cast<int>(value);
  return true;
}

// The problem of a face of `size` vertices, or "" when it can be a face.
inline std::string polygon_size_problem(std::size_t size) {
  return size < 3 ? "face with " + std::to_string(size) + " vertices (at least 3 needed)" : "";
}

// Fan-triangulates a polygon into `faces`; returns the problem, or "" when the polygon is valid.
inline std::string add_polygon(const std::vector<double>& polygon, std::size_t vertex_count,
                               std::vector<Face>& faces) {
  if (polygon.size() < 3) return polygon_size_problem(polygon.size());
  std::vector<int> indices(polygon.size());
  for (std::size_t k = 0; k < polygon.size(); ++k)
    if (!to_index(polygon[k], vertex_count, indices[k])) {
      std::ostringstream problem;
      problem << "vertex index " << polygon[k] << " out of range (" << vertex_count << " vertices)";
      return problem.str();
    }
  for (std::size_t k = 1; k + 1 < indices.size(); ++k)
    faces.push_back({indices[0], indices[k], indices[k + 1]});
  return "";
}

// Collects points whose normals may be given for some and missing for others. Missing normals
// become NaN so that clean_surface drops those points; without any normal, none are stored.
class PointSink {
 public:
  void add(const Vec3& point) {
    surface_.points.push_back(point);
    if (!surface_.normals.empty()) surface_.normals.push_back(Vec3::Constant(kNaN));
  }
  void add_with_normal(const Vec3& point, const Vec3& normal) {
    surface_.normals.resize(surface_.points.size(), Vec3::Constant(kNaN));
    surface_.points.push_back(point);
    surface_.normals.push_back(normal);
  }
  std::vector<Face>& faces() { return surface_.faces; }
  SurfaceInput finish() { return std::move(surface_); }

 private:
  SurfaceInput surface_;
};

// ---------------------------------------------------------------------------------------------
// Binary scalars (PLY bodies, PCD fields)

enum class ScalarType {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kInt64,
  kUint64,
  kFloat32,
  kFloat64
};

inline std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
    case ScalarType::kUint8:
      return 1;
    case ScalarType::kInt16:
    case ScalarType::kUint16:
      return 2;
    case ScalarType::kInt32:
    case ScalarType::kUint32:
    case ScalarType::kFloat32:
      return 4;
    default:
      return 8;
  }
}

template <typename T>
inline double load(const char* raw) {
  T value;
  std::memcpy(&value, raw, sizeof value);
  return static_cast<double>(value);
}

// Reads one value at `cursor` and advances it; false (cursor unchanged) if the data ends first.
inline bool read_scalar(const char*& cursor, const char* end, ScalarType type, bool swap,
                        double& value) {
  const std::size_t size = scalar_size(type);
  if (static_cast<std::size_t>(end - cursor) < size) return false;
  char raw[8];
  std::memcpy(raw, cursor, size);
  if (swap) std::reverse(raw, raw + size);
  cursor += size;
  switch (type) {
    case ScalarType::kInt8:
      value = load<std::int8_t>(raw);
      break;
    case ScalarType::kUint8:
      value = load<std::uint8_t>(raw);
      break;
    case ScalarType::kInt16:
      value = load<std::int16_t>(raw);
      break;
    case ScalarType::kUint16:
      value = load<std::uint16_t>(raw);
      break;
    case ScalarType::kInt32:
      value = load<std::int32_t>(raw);
      break;
    case ScalarType::kUint32:
      value = load<std::uint32_t>(raw);
      break;
    case ScalarType::kInt64:
      value = load<std::int64_t>(raw);
      break;
    case ScalarType::kUint64:
      value = load<std::uint64_t>(raw);
      break;
    case ScalarType::kFloat32:
      value = load<float>(raw);
      break;
    case ScalarType::kFloat64:
      value = load<double>(raw);
      break;
  }
  return true;
}

inline constexpr const char* kSphereOutOfRange =
    "sphere out of range (non-finite, or a value beyond 1e150)";

inline bool in_range(const Sphere& sphere) {
  return (sphere.center.array().abs() <= kMaxCoordinate).all() &&
         std::abs(sphere.radius) <= kMaxCoordinate;  // false for NaN too
}

// The whole file in memory (no regrowth: 1x its size); fails if it is missing, a directory or
// empty, and, before reading it all, if its first bytes cannot start a file of `extension`
// (a PLY without its 'ply' line; a NUL byte in a text format): a 2 GB file of zeros is refused
// after 4 KB.
std::string read_file(const std::string& path, const std::string& extension);

// Fails unless `start` (a file's first bytes) begins with PLY's 'ply' line.
void check_ply_start(const std::string& path, std::string_view start);

// One reader per format (io_FORMAT.cpp); each fails with "PATH: problem".
SurfaceInput parse_off(const std::string& path, std::string_view text);
SurfaceInput parse_obj(const std::string& path, std::string_view text);
// `density_field` (empty: none): the per-point value read into SurfaceInput::density (a PLY
// vertex property, a PCD field, an .xyz's last column of 4 or 7).
SurfaceInput parse_xyz(const std::string& path, std::string_view text,
                       const std::string& density_field = {});
SurfaceInput parse_ply_surface(const std::string& path, std::string_view bytes,
                               const std::string& density_field = {});
SurfaceInput read_pcd(const std::string& path, const std::string& density_field = {});
MedialMesh parse_ply_medial(const std::string& path, std::string_view bytes);
MedialMesh parse_ma(const std::string& path, std::string_view text);

}  // namespace io_internal
}  // namespace vmas
