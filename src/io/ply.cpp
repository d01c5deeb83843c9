// PLY reader (ASCII, binary little- and big-endian): shapes and medial meshes.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {
namespace {

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

}  // namespace

void check_ply_start(const std::string& path, std::string_view start) {
  const std::size_t line_end = start.find('\n');
  if (start.substr(0, 3) != "ply" || line_end == std::string_view::npos ||
      trim(start.substr(0, line_end)) != "ply")
    fail(path, "bad header: not a PLY file (no 'ply' first line)");
}

namespace {

// Parses the header; returns the offset of the body and sets `header_lines`.
std::size_t parse_ply_header(const std::string& path, std::string_view bytes, PlyFile& ply,
                             std::size_t& header_lines) {
  check_ply_start(path, bytes);
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

// A face list too short to be a face fails at once: a file of empty lists would otherwise be
// stored whole (8 bytes of list start per byte of file) before the first one is looked at.
void check_face_size(const std::string& path, const PlyElement& element, std::size_t item,
                     std::size_t length) {
  if (element.name != "face") return;
  const std::string problem = polygon_size_problem(length);
  if (!problem.empty()) fail(path, "face " + std::to_string(item) + ": " + problem);
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
          check_face_size(path, element, item, length);
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
        check_face_size(path, element, item, length);
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

}  // namespace

SurfaceInput parse_ply_surface(const std::string& path, std::string_view bytes,
                               const std::string& density_field) {
  const PlyFile ply = read_ply(path, bytes, {"vertex", "face"});
  const PlyElement* vertex = ply.find("vertex");
  if (!vertex) fail(path, "no 'vertex' element");
  const auto& x = ply_column(path, *vertex, {"x"});
  const auto& y = ply_column(path, *vertex, {"y"});
  const auto& z = ply_column(path, *vertex, {"z"});
  const bool has_normals = vertex->find({"nx"}) && vertex->find({"ny"}) && vertex->find({"nz"});
  SurfaceInput surface;
  surface.points.reserve(vertex->count);
  for (std::size_t i = 0; i < vertex->count; ++i) surface.points.emplace_back(x[i], y[i], z[i]);
  if (has_normals) {
    const auto& nx = ply_column(path, *vertex, {"nx"});
    const auto& ny = ply_column(path, *vertex, {"ny"});
    const auto& nz = ply_column(path, *vertex, {"nz"});
    surface.normals.reserve(vertex->count);
    for (std::size_t i = 0; i < vertex->count; ++i)
      surface.normals.emplace_back(nx[i], ny[i], nz[i]);
  }
  if (!density_field.empty()) {
    const PlyProperty* density = vertex->find({density_field});
    if (!density || density->is_list) {
      std::string names;
      for (const PlyProperty& property : vertex->properties)
        if (!property.is_list) names += (names.empty() ? "" : " ") + property.name;
      fail(path, "no vertex property " + quote(density_field) +
                     " for the density (properties: " + names + ")");
    }
    surface.density = density->values;
  }
  surface.faces = ply_faces(path, ply, vertex->count);
  return surface;
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

}  // namespace vmas::io_internal
