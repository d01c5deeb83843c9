// Readers of the IO stage (one tokenizer and one PLY parser for every format) and clean_surface.
#include "vmas/io.hpp"

#include <pcl/io/lzf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <tuple>
#include <vector>

#include "io_internal.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace {

using io_internal::fail;
using io_internal::host_is_little_endian;
using io_internal::lower_extension;
using io_internal::quote;

using Face = std::array<int, 3>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Coordinates beyond this make squared distances overflow.
constexpr double kMaxCoordinate = 1e150;

// Fails with a clear message for the usual reasons a path cannot be read.
void check_readable(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "no such file");
  if (std::filesystem::is_directory(status)) fail(path, "is a directory");
  if (std::filesystem::file_size(path, error) == 0 && !error) fail(path, "empty file");
}

std::string read_file(const std::string& path) {
  check_readable(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::string bytes(std::filesystem::file_size(path), '\0');  // no regrowth: 1x the file
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) fail(path, "read error");
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (bytes.empty()) fail(path, "empty file");
  return bytes;
}

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\v' || c == '\f';
}

std::string_view trim(std::string_view text) {
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
    vmas::fail(path_, "line " + std::to_string(line_) + ": " + problem);
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
bool to_index(double value, std::size_t count, int& index) {
  const double end =
      static_cast<double>(std::min<std::size_t>(count, std::numeric_limits<int>::max()));
  if (!(value >= 0.0 && value < end) || value != std::floor(value)) return false;
  index = static_cast<int>(value);
  return true;
}

// Fan-triangulates a polygon into `faces`; returns the problem, or "" when the polygon is valid.
std::string add_polygon(const std::vector<double>& polygon, std::size_t vertex_count,
                        std::vector<Face>& faces) {
  if (polygon.size() < 3)
    return "face with " + std::to_string(polygon.size()) + " vertices (at least 3 needed)";
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

std::size_t scalar_size(ScalarType type) {
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
double load(const char* raw) {
  T value;
  std::memcpy(&value, raw, sizeof value);
  return static_cast<double>(value);
}

// Reads one value at `cursor` and advances it; false (cursor unchanged) if the data ends first.
bool read_scalar(const char*& cursor, const char* end, ScalarType type, bool swap, double& value) {
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

// ---------------------------------------------------------------------------------------------
// PLY

bool parse_ply_type(std::string_view name, ScalarType& type) {
  static const std::pair<std::string_view, ScalarType> kTypes[] = {
      {"char", ScalarType::kInt8},      {"int8", ScalarType::kInt8},
      {"uchar", ScalarType::kUint8},    {"uint8", ScalarType::kUint8},
      {"short", ScalarType::kInt16},    {"int16", ScalarType::kInt16},
      {"ushort", ScalarType::kUint16},  {"uint16", ScalarType::kUint16},
      {"int", ScalarType::kInt32},      {"int32", ScalarType::kInt32},
      {"uint", ScalarType::kUint32},    {"uint32", ScalarType::kUint32},
      {"float", ScalarType::kFloat32},  {"float32", ScalarType::kFloat32},
      {"double", ScalarType::kFloat64}, {"float64", ScalarType::kFloat64}};
  for (const auto& [type_name, value] : kTypes)
    if (type_name == name) {
      type = value;
      return true;
    }
  return false;
}

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::kFloat32;  // the value type (of each entry, for lists)
  bool is_list = false;
  ScalarType count_type = ScalarType::kUint8;
  // Filled for wanted elements only: one value per item, or for lists every item's entries in
  // a row, item i owning values[list_starts[i] .. list_starts[i + 1]).
  std::vector<double> values;
  std::vector<std::size_t> list_starts{0};
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;

  const PlyProperty* find(std::initializer_list<std::string_view> names) const {
    for (const PlyProperty& property : properties)
      for (std::string_view name : names)
        if (property.name == name) return &property;
    return nullptr;
  }
};

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyFile {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;

  const PlyElement* find(std::string_view name) const {
    for (const PlyElement& element : elements)
      if (element.name == name) return &element;
    return nullptr;
  }
};

// Parses the header; returns the offset of the body and sets `header_lines`.
std::size_t parse_ply_header(const std::string& path, std::string_view bytes, PlyFile& ply,
                             std::size_t& header_lines) {
  if (bytes.substr(0, 3) != "ply" || trim(bytes.substr(0, bytes.find('\n'))) != "ply")
    fail(path, "bad header: not a PLY file (no 'ply' first line)");
  std::size_t body = std::string_view::npos;
  std::size_t end_line_start = 0;
  header_lines = 0;
  for (std::size_t position = 0; position < bytes.size();) {
    const std::size_t end = bytes.find('\n', position);
    if (end == std::string_view::npos) break;
    ++header_lines;
    if (trim(bytes.substr(position, end - position)) == "end_header") {
      end_line_start = position;
      body = end + 1;
      break;
    }
    position = end + 1;
  }
  if (body == std::string_view::npos) fail(path, "bad header: no end_header line");

  LineTokenizer header(path, bytes.substr(0, end_line_start));
  std::vector<std::string_view> tokens;
  header.next(tokens);  // "ply"
  bool has_format = false;
  while (header.next(tokens)) {
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (tokens.size() < 2) header.fail("bad header: incomplete format line");
      if (tokens[1] == "ascii")
        ply.format = PlyFormat::kAscii;
      else if (tokens[1] == "binary_little_endian")
        ply.format = PlyFormat::kBinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        ply.format = PlyFormat::kBinaryBigEndian;
      else
        header.fail("bad header: unknown format " + quote(tokens[1]));
      has_format = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) header.fail("bad header: expected 'element NAME COUNT'");
      ply.elements.push_back({std::string(tokens[1]), header.count(tokens[2]), {}});
    } else if (keyword == "property") {
      if (ply.elements.empty()) header.fail("bad header: property before any element");
      PlyProperty property;
      property.is_list = tokens.size() > 1 && tokens[1] == "list";
      const std::size_t expected = property.is_list ? 5 : 3;
      if (tokens.size() != expected)
        header.fail("bad header: expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
      if (property.is_list && !parse_ply_type(tokens[2], property.count_type))
        header.fail("bad header: unknown type " + quote(tokens[2]));
      if (property.is_list && (property.count_type == ScalarType::kFloat32 ||
                               property.count_type == ScalarType::kFloat64))
        header.fail("bad header: list length type must be an integer type");
      if (!parse_ply_type(tokens[expected - 2], property.type))
        header.fail("bad header: unknown type " + quote(tokens[expected - 2]));
      property.name = tokens[expected - 1];
      ply.elements.back().properties.push_back(std::move(property));
    } else {
      header.fail("bad header: unknown keyword " + quote(keyword));
    }
  }
  if (!has_format) fail(path, "bad header: no format line");
  for (const PlyElement& element : ply.elements)
    if (element.properties.empty() && element.count > 0)
      fail(path, "bad header: element '" + element.name + "' has no properties");
  return body;
}

[[noreturn]] void fail_truncated(const std::string& path, const PlyElement& element,
                                 std::size_t item) {
  fail(path, "truncated: element '" + element.name + "' ends after " + std::to_string(item) +
                 " of " + std::to_string(element.count) + " items");
}

// Reads a PLY file; only the elements named in `wanted` get their values stored.
PlyFile read_ply(const std::string& path, std::string_view bytes,
                 std::initializer_list<std::string_view> wanted) {
  PlyFile ply;
  std::size_t header_lines = 0;
  const std::size_t body = parse_ply_header(path, bytes, ply, header_lines);
  const auto is_wanted = [&](const PlyElement& element) {
    return std::find(wanted.begin(), wanted.end(), element.name) != wanted.end();
  };

  if (ply.format != PlyFormat::kAscii) {
    const bool big_endian = ply.format == PlyFormat::kBinaryBigEndian;
    const bool swap = big_endian == host_is_little_endian();
    const char* cursor = bytes.data() + body;
    const char* const end = bytes.data() + bytes.size();
    for (PlyElement& element : ply.elements) {
      const bool keep = is_wanted(element);
      for (std::size_t item = 0; item < element.count; ++item) {
        for (PlyProperty& property : element.properties) {
          double value = 0.0;
          if (!read_scalar(cursor, end, property.is_list ? property.count_type : property.type,
                           swap, value))
            fail_truncated(path, element, item);
          if (!property.is_list) {
            if (keep) property.values.push_back(value);
            continue;
          }
          const std::size_t size = scalar_size(property.type);
          if (!(value >= 0.0)) fail(path, "negative list length in element '" + element.name + "'");
          if (value > static_cast<double>(end - cursor) / size) fail_truncated(path, element, item);
          const auto length = static_cast<std::size_t>(value);
          if (!keep) {
            cursor += length * size;
            continue;
          }
          for (std::size_t k = 0; k < length; ++k) {
            read_scalar(cursor, end, property.type, swap, value);
            property.values.push_back(value);
          }
          property.list_starts.push_back(property.values.size());
        }
      }
    }
    return ply;
  }

  LineTokenizer lines(path, bytes.substr(body), header_lines);
  std::vector<std::string_view> tokens;
  for (PlyElement& element : ply.elements) {
    const bool keep = is_wanted(element);
    for (std::size_t item = 0; item < element.count; ++item) {
      if (!lines.next(tokens)) fail_truncated(path, element, item);
      std::size_t next = 0;
      const auto take = [&]() {
        if (next >= tokens.size())
          lines.fail("too few values for an item of element '" + element.name + "'");
        return tokens[next++];
      };
      for (PlyProperty& property : element.properties) {
        if (!property.is_list) {
          const std::string_view token = take();
          if (keep) property.values.push_back(lines.number(token));
          continue;
        }
        const std::size_t length = lines.count(take());
        for (std::size_t k = 0; k < length; ++k) {
          const std::string_view token = take();
          if (keep) property.values.push_back(lines.number(token));
        }
        if (keep) property.list_starts.push_back(property.values.size());
      }
      if (next != tokens.size())
        lines.fail("too many values for an item of element '" + element.name + "'");
    }
  }
  return ply;
}

// The column of a scalar vertex property, or a failure naming it.
const std::vector<double>& ply_column(const std::string& path, const PlyElement& element,
                                      std::initializer_list<std::string_view> names) {
  const PlyProperty* property = element.find(names);
  if (!property || property->is_list)
    fail(path, "element '" + element.name + "' has no scalar property '" +
                   std::string(*names.begin()) + "'");
  return property->values;
}

std::vector<Face> ply_faces(const std::string& path, const PlyFile& ply, std::size_t vertex_count) {
  std::vector<Face> faces;
  const PlyElement* element = ply.find("face");
  if (!element || element->count == 0) return faces;
  const PlyProperty* indices = element->find({"vertex_indices", "vertex_index"});
  if (!indices || !indices->is_list) fail(path, "element 'face' has no vertex_indices list");
  for (std::size_t i = 0; i < element->count; ++i) {
    const std::vector<double> polygon(indices->values.begin() + indices->list_starts[i],
                                      indices->values.begin() + indices->list_starts[i + 1]);
    const std::string problem = add_polygon(polygon, vertex_count, faces);
    if (!problem.empty()) fail(path, "face " + std::to_string(i) + ": " + problem);
  }
  return faces;
}

SurfaceInput parse_ply_surface(const std::string& path, std::string_view bytes) {
  const PlyFile ply = read_ply(path, bytes, {"vertex", "face"});
  const PlyElement* vertex = ply.find("vertex");
  if (!vertex) fail(path, "no 'vertex' element");
  const auto& x = ply_column(path, *vertex, {"x"});
  const auto& y = ply_column(path, *vertex, {"y"});
  const auto& z = ply_column(path, *vertex, {"z"});
  const bool has_normals = vertex->find({"nx"}) && vertex->find({"ny"}) && vertex->find({"nz"});
  SurfaceInput surface;
  for (std::size_t i = 0; i < vertex->count; ++i) surface.points.emplace_back(x[i], y[i], z[i]);
  if (has_normals) {
    const auto& nx = ply_column(path, *vertex, {"nx"});
    const auto& ny = ply_column(path, *vertex, {"ny"});
    const auto& nz = ply_column(path, *vertex, {"nz"});
    for (std::size_t i = 0; i < vertex->count; ++i)
      surface.normals.emplace_back(nx[i], ny[i], nz[i]);
  }
  surface.faces = ply_faces(path, ply, vertex->count);
  return surface;
}

// ---------------------------------------------------------------------------------------------
// OFF, OBJ, XYZ, PCD

SurfaceInput parse_off(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens)) fail(path, "bad header: no OFF line");
  const std::string_view keyword = tokens[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    lines.fail("bad header: expected OFF, NOFF or COFF, found " + quote(keyword));
  // NOFF promises a normal after each vertex; files that say NOFF but give none load without.
  const bool normals_announced =
      keyword.substr(0, keyword.size() - 3).find('N') != std::string_view::npos;
  std::size_t first = 1;
  if (tokens.size() == 1) {
    if (!lines.next(tokens)) fail(path, "bad header: no vertex and face counts");
    first = 0;
  }
  if (tokens.size() < first + 2) lines.fail("bad header: expected vertex and face counts");
  const std::size_t vertex_count = lines.count(tokens[first]);
  const std::size_t face_count = lines.count(tokens[first + 1]);

  PointSink sink;
  for (std::size_t i = 0; i < vertex_count; ++i) {
    if (!lines.next(tokens))
      fail(path,
           "truncated: " + std::to_string(i) + " of " + std::to_string(vertex_count) + " vertices");
    if (tokens.size() < 3) lines.fail("expected x y z");
    if (normals_announced && tokens.size() >= 6)
      sink.add_with_normal(lines.vec3(tokens, 0), lines.vec3(tokens, 3));
    else
      sink.add(lines.vec3(tokens, 0));
  }
  std::vector<double> polygon;
  for (std::size_t i = 0; i < face_count; ++i) {
    if (!lines.next(tokens))
      fail(path,
           "truncated: " + std::to_string(i) + " of " + std::to_string(face_count) + " faces");
    const std::size_t size = lines.count(tokens[0]);
    if (size > tokens.size() - 1) lines.fail("face lists fewer indices than its size");
    polygon.clear();
    for (std::size_t k = 1; k <= size; ++k) polygon.push_back(lines.integer(tokens[k]));
    const std::string problem = add_polygon(polygon, vertex_count, sink.faces());
    if (!problem.empty()) lines.fail(problem);
  }
  return sink.finish();
}

SurfaceInput parse_obj(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  SurfaceInput surface;
  std::vector<double> polygon;
  while (lines.next(tokens)) {
    const std::string_view keyword = tokens[0];
    if (keyword == "v" || keyword == "vn") {
      if (tokens.size() < 4) lines.fail("expected 3 coordinates after " + quote(keyword));
      (keyword == "v" ? surface.points : surface.normals).push_back(lines.vec3(tokens, 1));
    } else if (keyword == "f") {
      // A bare "f" (trimesh writes one for point clouds) holds no face.
      if (tokens.size() == 1) continue;
      polygon.clear();
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        const std::string_view token = tokens[k];
        const long long index = lines.integer(token.substr(0, token.find('/')));
        if (index == 0) lines.fail("vertex index 0 (OBJ indices start at 1)");
        // Negative indices count back from the last vertex read so far.
        polygon.push_back(static_cast<double>(
            index < 0 ? static_cast<long long>(surface.points.size()) + index : index - 1));
      }
      const std::string problem = add_polygon(polygon, surface.points.size(), surface.faces);
      if (!problem.empty()) lines.fail(problem);
    }
  }
  // Normals can be matched to points only in a cloud listing exactly one per point.
  if (surface.is_mesh() || surface.normals.size() != surface.points.size()) surface.normals.clear();
  return surface;
}

SurfaceInput parse_xyz(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  PointSink sink;
  while (lines.next(tokens)) {
    if (tokens.size() == 3)
      sink.add(lines.vec3(tokens, 0));
    else if (tokens.size() == 6)
      sink.add_with_normal(lines.vec3(tokens, 0), lines.vec3(tokens, 3));
    else
      lines.fail("expected 3 or 6 columns (x y z [nx ny nz]), found " +
                 std::to_string(tokens.size()));
  }
  return sink.finish();
}

// PCD is read here rather than by pcl::PCDReader, which trusts the header: a malformed one
// crashes it, and a large POINTS makes it allocate before it compares with the file size.

struct PcdField {
  std::string_view name;
  std::size_t size = 4;  // bytes of one value
  char type = 'F';       // I, U or F
  std::size_t count = 1;
  ScalarType scalar = ScalarType::kFloat32;
  std::size_t offset = 0;  // of its first value in a point of DATA binary
  std::size_t value = 0;   // index of its first value on a line of DATA ascii
  std::size_t block = 0;   // of its first value in unpacked DATA binary_compressed
};

// No usable point needs more bytes (PCL's largest descriptors take a few KB).
constexpr std::size_t kPcdMaxPointBytes = std::size_t{1} << 16;
// LZF output is at most 88 times its input: a 3-byte back reference yields 264 bytes.
constexpr std::size_t kLzfMaxExpansion = 88;

bool pcd_scalar(char type, std::size_t size, ScalarType& scalar) {
  static const std::tuple<char, std::size_t, ScalarType> kTypes[] = {
      {'I', 1, ScalarType::kInt8},   {'I', 2, ScalarType::kInt16},  {'I', 4, ScalarType::kInt32},
      {'I', 8, ScalarType::kInt64},  {'U', 1, ScalarType::kUint8},  {'U', 2, ScalarType::kUint16},
      {'U', 4, ScalarType::kUint32}, {'U', 8, ScalarType::kUint64}, {'F', 4, ScalarType::kFloat32},
      {'F', 8, ScalarType::kFloat64}};
  for (const auto& [t, s, value] : kTypes)
    if (t == type && s == size) {
      scalar = value;
      return true;
    }
  return false;
}

SurfaceInput read_pcd(const std::string& path) {
  const std::string bytes = read_file(path);
  LineTokenizer lines(path, bytes);
  std::vector<std::string_view> tokens;
  std::vector<PcdField> fields;
  bool has_fields = false, has_size = false, has_type = false;
  std::size_t width = 0, height = 0, points = 0;
  bool has_width = false, has_height = false, has_points = false;
  std::string_view data;
  while (data.empty()) {
    if (!lines.next(tokens)) fail(path, "bad PCD header: no DATA line");
    const std::string_view keyword = tokens[0];
    const auto one_per_field = [&]() {
      if (!has_fields) lines.fail("bad PCD header: " + std::string(keyword) + " before FIELDS");
      if (tokens.size() != fields.size() + 1)
        lines.fail("bad PCD header: " + std::to_string(tokens.size() - 1) + " " +
                   std::string(keyword) + " entries for " + std::to_string(fields.size()) +
                   " fields");
    };
    const auto number = [&](bool& seen) {
      if (tokens.size() != 2)
        lines.fail("bad PCD header: expected '" + std::string(keyword) + " N'");
      seen = true;
      return lines.count(tokens[1]);
    };
    if (keyword == "VERSION" || keyword == "VIEWPOINT") continue;
    if (keyword == "FIELDS" || keyword == "COLUMNS") {
      if (tokens.size() < 2) lines.fail("bad PCD header: no field names");
      fields.assign(tokens.size() - 1, PcdField{});
      for (std::size_t f = 0; f < fields.size(); ++f) fields[f].name = tokens[f + 1];
      has_fields = true;
    } else if (keyword == "SIZE") {
      one_per_field();
      for (std::size_t f = 0; f < fields.size(); ++f) fields[f].size = lines.count(tokens[f + 1]);
      has_size = true;
    } else if (keyword == "TYPE") {
      one_per_field();
      for (std::size_t f = 0; f < fields.size(); ++f) {
        if (tokens[f + 1].size() != 1)
          lines.fail("bad PCD header: unknown type " + quote(tokens[f + 1]));
        fields[f].type = tokens[f + 1][0];
      }
      has_type = true;
    } else if (keyword == "COUNT") {  // optional, 1 by default
      one_per_field();
      for (std::size_t f = 0; f < fields.size(); ++f) {
        fields[f].count = lines.count(tokens[f + 1]);
        if (fields[f].count == 0 || fields[f].count > kPcdMaxPointBytes)
          lines.fail("bad PCD header: COUNT " + quote(tokens[f + 1]) + " out of range");
      }
    } else if (keyword == "WIDTH") {
      width = number(has_width);
    } else if (keyword == "HEIGHT") {
      height = number(has_height);
    } else if (keyword == "POINTS") {
      points = number(has_points);
    } else if (keyword == "DATA") {
      if (tokens.size() != 2 ||
          (tokens[1] != "ascii" && tokens[1] != "binary" && tokens[1] != "binary_compressed"))
        lines.fail(
            "bad PCD header: expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
      data = tokens[1];
    } else {
      lines.fail("bad PCD header: unknown keyword " + quote(keyword));
    }
  }
  const std::pair<bool, const char*> kRequired[] = {{has_fields, "FIELDS"}, {has_size, "SIZE"},
                                                    {has_type, "TYPE"},     {has_width, "WIDTH"},
                                                    {has_height, "HEIGHT"}, {has_points, "POINTS"}};
  for (const auto& [seen, keyword] : kRequired)
    if (!seen) fail(path, std::string("bad PCD header: no ") + keyword + " line");
  if (width * height != points || (width != 0 && points / width != height))
    fail(path, "bad PCD header: WIDTH " + std::to_string(width) + " x HEIGHT " +
                   std::to_string(height) + " is not POINTS " + std::to_string(points));

  std::size_t point_step = 0, values_per_point = 0, packed_step = 0;
  for (PcdField& field : fields) {
    if (!pcd_scalar(field.type, field.size, field.scalar))
      fail(path, "bad PCD header: field '" + std::string(field.name) + "' has unsupported TYPE " +
                     quote(std::string(1, field.type)) + " with SIZE " +
                     std::to_string(field.size));
    field.offset = point_step;
    field.value = values_per_point;
    point_step += field.size * field.count;  // each term <= 8 * kPcdMaxPointBytes: no overflow
    values_per_point += field.count;
    if (field.name != "_") packed_step += field.size * field.count;  // "_" pads binary points
    if (point_step > kPcdMaxPointBytes)
      fail(path,
           "bad PCD header: points of more than " + std::to_string(kPcdMaxPointBytes) + " bytes");
  }
  const auto find = [&](std::string_view name) -> const PcdField* {
    for (const PcdField& field : fields)
      if (field.name == name) return &field;
    return nullptr;
  };
  const PcdField* columns[6];
  const char* const kNames[6] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (int c = 0; c < 6; ++c) columns[c] = find(kNames[c]);
  if (!columns[0] || !columns[1] || !columns[2]) fail(path, "PCD file has no x, y, z fields");
  const int wanted = columns[3] && columns[4] && columns[5] ? 6 : 3;

  SurfaceInput surface;
  const auto add = [&](const double(&values)[6]) {
    surface.points.emplace_back(values[0], values[1], values[2]);
    if (wanted == 6) surface.normals.emplace_back(values[3], values[4], values[5]);
  };
  const std::string_view body = std::string_view(bytes).substr(lines.position());
  if (data == "ascii") {
    LineTokenizer rows(path, body, lines.line());
    double values[6] = {};
    while (rows.next(tokens)) {
      if (surface.points.size() == points)
        rows.fail("more points than POINTS " + std::to_string(points));
      if (tokens.size() != values_per_point)
        rows.fail("expected " + std::to_string(values_per_point) + " values, found " +
                  std::to_string(tokens.size()));
      for (int c = 0; c < wanted; ++c) {
        values[c] = rows.number(tokens[columns[c]->value]);
        // As if stored in the field's type, like the binary formats (and PCL)
        if (columns[c]->scalar == ScalarType::kFloat32) values[c] = static_cast<float>(values[c]);
      }
      add(values);
    }
    if (surface.points.size() < points)
      fail(path, "truncated: " + std::to_string(surface.points.size()) + " of " +
                     std::to_string(points) + " points");
    return surface;
  }

  // PCL writes binary data in the host's order, which is little-endian everywhere it runs.
  const bool swap = !host_is_little_endian();
  const auto read_points = [&](const char* start, auto&& at) {
    double values[6] = {};
    for (std::size_t i = 0; i < points; ++i) {
      for (int c = 0; c < wanted; ++c) {
        const char* cursor = start + at(*columns[c], i);
        read_scalar(cursor, cursor + columns[c]->size, columns[c]->scalar, swap, values[c]);
      }
      add(values);
    }
  };
  if (data == "binary") {
    if (points > body.size() / point_step)
      fail(path, "truncated: PCD data of " + std::to_string(body.size()) + " bytes, too few for " +
                     std::to_string(points) + " points of " + std::to_string(point_step) +
                     " bytes");
    read_points(body.data(), [&](const PcdField& field, std::size_t i) {
      return i * point_step + field.offset;
    });
    return surface;
  }

  // binary_compressed: two 32-bit sizes, then LZF data that unpacks to one block per field
  // (all points' values of the first field, then of the second, ...), "_" fields left out.
  double sizes[2] = {};
  const char* cursor = body.data();
  for (double& size : sizes)
    if (!read_scalar(cursor, body.data() + body.size(), ScalarType::kUint32, swap, size))
      fail(path, "truncated: no compressed data sizes");
  const auto compressed = static_cast<std::size_t>(sizes[0]);
  const auto uncompressed = static_cast<std::size_t>(sizes[1]);
  if (compressed > body.size() - 8)
    fail(path, "truncated: " + std::to_string(compressed) +
                   " bytes of compressed data announced, " + std::to_string(body.size() - 8) +
                   " present");
  if (points > uncompressed / std::max<std::size_t>(packed_step, 1) ||
      uncompressed != points * packed_step)
    fail(path, "corrupt: " + std::to_string(uncompressed) + " uncompressed bytes for " +
                   std::to_string(points) + " points of " + std::to_string(packed_step) + " bytes");
  if (uncompressed > kLzfMaxExpansion * compressed)
    fail(path, "corrupt: " + std::to_string(compressed) + " compressed bytes cannot hold " +
                   std::to_string(uncompressed));
  if (points == 0) return surface;
  std::vector<char> unpacked(uncompressed);
  if (pcl::lzfDecompress(cursor, static_cast<unsigned>(compressed), unpacked.data(),
                         static_cast<unsigned>(uncompressed)) != uncompressed)
    fail(path,
         "corrupt: compressed data does not unpack to " + std::to_string(uncompressed) + " bytes");
  std::size_t start = 0;
  for (PcdField& field : fields) {
    field.block = start;
    if (field.name != "_") start += points * field.size * field.count;
  }
  read_points(unpacked.data(), [&](const PcdField& field, std::size_t i) {
    return field.block + i * field.size * field.count;
  });
  return surface;
}

// ---------------------------------------------------------------------------------------------
// Medial meshes

constexpr const char* kSphereOutOfRange =
    "sphere out of range (non-finite, or a value beyond 1e150)";

bool in_range(const Sphere& sphere) {
  return (sphere.center.array().abs() <= kMaxCoordinate).all() &&
         std::abs(sphere.radius) <= kMaxCoordinate;  // false for NaN too
}

MedialMesh parse_ma(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens) || tokens.size() < 3)
    fail(path, "bad header: expected 'vertex_count edge_count face_count'");
  const std::size_t counts[3] = {lines.count(tokens[0]), lines.count(tokens[1]),
                                 lines.count(tokens[2])};
  MedialMesh mesh;
  const auto index = [&](std::string_view token) {
    int value = 0;
    if (!to_index(static_cast<double>(lines.integer(token)), counts[0], value))
      lines.fail("vertex index " + std::string(token) + " out of range (" +
                 std::to_string(counts[0]) + " vertices)");
    return value;
  };
  while (lines.next(tokens)) {
    const std::string_view kind = tokens[0];
    const std::size_t needed = kind == "v" ? 5 : kind == "e" ? 3 : kind == "f" ? 4 : 0;
    if (needed == 0) lines.fail("unknown record " + quote(kind) + " (expected v, e or f)");
    if (tokens.size() < needed) lines.fail("expected " + std::to_string(needed - 1) + " values");
    if (kind == "v") {
      const Sphere sphere{lines.vec3(tokens, 1), lines.number(tokens[4])};
      if (!in_range(sphere)) lines.fail(kSphereOutOfRange);
      mesh.spheres.push_back(sphere);
    } else if (kind == "e") {
      mesh.edges.push_back({index(tokens[1]), index(tokens[2])});
    } else {
      mesh.faces.push_back({index(tokens[1]), index(tokens[2]), index(tokens[3])});
    }
  }
  const std::size_t found[3] = {mesh.spheres.size(), mesh.edges.size(), mesh.faces.size()};
  const char* const kNames[3] = {"vertices", "edges", "faces"};
  for (int k = 0; k < 3; ++k)
    if (found[k] != counts[k])
      fail(path, "header announces " + std::to_string(counts[k]) + " " + kNames[k] + " but " +
                     std::to_string(found[k]) + " were found");
  return mesh;
}

MedialMesh parse_ply_medial(const std::string& path, std::string_view bytes) {
  const PlyFile ply = read_ply(path, bytes, {"vertex", "edge", "face"});
  const PlyElement* vertex = ply.find("vertex");
  if (!vertex) fail(path, "no 'vertex' element");
  const auto& x = ply_column(path, *vertex, {"x"});
  const auto& y = ply_column(path, *vertex, {"y"});
  const auto& z = ply_column(path, *vertex, {"z"});
  const auto& radius = ply_column(path, *vertex, {"radius", "r"});
  MedialMesh mesh;
  for (std::size_t i = 0; i < vertex->count; ++i) {
    const Sphere sphere{Vec3(x[i], y[i], z[i]), radius[i]};
    if (!in_range(sphere)) fail(path, "vertex " + std::to_string(i) + ": " + kSphereOutOfRange);
    mesh.spheres.push_back(sphere);
  }
  if (const PlyElement* edge = ply.find("edge"); edge && edge->count > 0) {
    const auto& first = ply_column(path, *edge, {"vertex1"});
    const auto& second = ply_column(path, *edge, {"vertex2"});
    for (std::size_t i = 0; i < edge->count; ++i) {
      std::array<int, 2> ends{};
      if (!to_index(first[i], vertex->count, ends[0]) ||
          !to_index(second[i], vertex->count, ends[1]))
        fail(path, "edge " + std::to_string(i) + ": vertex index out of range (" +
                       std::to_string(vertex->count) + " vertices)");
      mesh.edges.push_back(ends);
    }
  }
  mesh.faces = ply_faces(path, ply, vertex->count);
  return mesh;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public functions

SurfaceInput read_surface(const std::string& path, CleanReport* report) {
  check_readable(path);  // "no such file" beats "unknown extension" for a mistyped path
  const std::string extension = lower_extension(path);
  SurfaceInput surface;
  if (extension == ".pcd") {
    surface = read_pcd(path);
  } else if (extension == ".off" || extension == ".ply" || extension == ".obj" ||
             extension == ".xyz" || extension == ".txt") {
    const std::string bytes = read_file(path);
    if (extension == ".off")
      surface = parse_off(path, bytes);
    else if (extension == ".ply")
      surface = parse_ply_surface(path, bytes);
    else if (extension == ".obj")
      surface = parse_obj(path, bytes);
    else
      surface = parse_xyz(path, bytes);
  } else {
    fail(path, "unknown file extension " + quote(extension) +
                   " (expected .off, .ply, .obj, .xyz, .txt or .pcd)");
  }
  if (surface.points.empty()) fail(path, "no points");
  CleanReport cleaned;
  try {
    cleaned = clean_surface(surface);
  } catch (const InvalidInput& error) {
    fail(path, error.what());
  }
  if (surface.points.empty()) fail(path, "no usable points");
  if (report) *report = cleaned;
  return surface;
}

CleanReport clean_surface(SurfaceInput& surface) {
  CleanReport report;
  const std::size_t count = surface.points.size();
  const bool with_normals = surface.has_normals();
  if (with_normals && surface.normals.size() != count)
    throw InvalidInput(std::to_string(surface.normals.size()) + " normals for " +
                       std::to_string(count) + " points");
  const auto& points = surface.points;

  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c)
      if (std::isinf(points[i][c]) || std::abs(points[i][c]) > kMaxCoordinate) {
        std::ostringstream problem;
        problem << "point " << i << ": coordinate " << points[i][c]
                << " out of range (must be finite and at most 1e150 in magnitude)";
        throw InvalidInput(problem.str());
      }
    const bool finite = points[i].allFinite() &&
                        (!with_normals ||
                         (surface.normals[i].allFinite() && surface.normals[i].stableNorm() > 0.0));
    if (finite)
      usable.push_back(i);
    else
      ++report.non_finite_points;
  }

  // Sorting by coordinates, then by index, makes the first occurrence of each point its
  // representative, independently of any hashing.
  constexpr std::size_t kDropped = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> representative(count, kDropped);
  std::sort(usable.begin(), usable.end(), [&](std::size_t a, std::size_t b) {
    for (int c = 0; c < 3; ++c)
      if (points[a][c] != points[b][c]) return points[a][c] < points[b][c];
    return a < b;
  });
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = -low;
  for (std::size_t k = 0; k < usable.size(); ++k) {
    const std::size_t i = usable[k];
    const bool duplicate = k > 0 && points[i] == points[usable[k - 1]];
    representative[i] = duplicate ? representative[usable[k - 1]] : i;
    if (duplicate) ++report.duplicate_points;
    low = low.cwiseMin(points[i]);
    high = high.cwiseMax(points[i]);
  }

  const double min_area = usable.empty() ? 0.0 : 1e-14 * (high - low).squaredNorm();
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<bool> referenced(count, false);
  for (const Face& face : surface.faces) {
    std::array<std::size_t, 3> corners{};
    bool degenerate = false;
    for (int c = 0; c < 3; ++c) {
      corners[c] = face[c] >= 0 && static_cast<std::size_t>(face[c]) < count
                       ? representative[face[c]]
                       : kDropped;
      degenerate = degenerate || corners[c] == kDropped;
    }
    degenerate = degenerate || corners[0] == corners[1] || corners[1] == corners[2] ||
                 corners[0] == corners[2] ||
                 0.5 * (points[corners[1]] - points[corners[0]])
                             .cross(points[corners[2]] - points[corners[0]])
                             .norm() <
                     min_area;
    if (degenerate) {
      ++report.degenerate_faces;
      continue;
    }
    faces.push_back(corners);
    for (std::size_t corner : corners) referenced[corner] = true;
  }

  const bool mesh = surface.is_mesh();
  std::vector<int> new_index(count, -1);
  SurfaceInput cleaned;
  for (std::size_t i = 0; i < count; ++i) {
    if (representative[i] != i) continue;
    if (mesh && !referenced[i]) {
      ++report.unused_points;
      continue;
    }
    new_index[i] = static_cast<int>(cleaned.points.size());
    cleaned.points.push_back(points[i]);
    if (with_normals)
      cleaned.normals.push_back(surface.normals[i] / surface.normals[i].stableNorm());
  }
  for (const auto& corners : faces)
    cleaned.faces.push_back({new_index[corners[0]], new_index[corners[1]], new_index[corners[2]]});
  surface = std::move(cleaned);
  return report;
}

MedialMesh read_medial_mesh(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension != ".ma" && extension != ".ply")
    fail(path, "unknown medial mesh extension " + quote(extension) + " (expected .ply or .ma)");
  const std::string bytes = read_file(path);
  return extension == ".ma" ? parse_ma(path, bytes) : parse_ply_medial(path, bytes);
}

}  // namespace vmas
