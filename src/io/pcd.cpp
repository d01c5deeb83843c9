// PCD reader (ascii, binary, binary_compressed), written for vmas rather than
// pcl::PCDReader, which trusts the header: a malformed one crashes it, and a large POINTS makes it
// allocate before it compares with the file size. LZF data is unpacked by Debian's liblzf (the
// format PCL writes; PCL's own copy lives in libpcl_io, which drags in VTK at every start-up).
#include <liblzf/lzf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {
namespace {

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

// What a PCD header says: the fields and their layout in a point, the point count and the
// encoding of the data.
struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t points = 0;
  std::string_view data;  // ascii, binary or binary_compressed
  std::size_t point_step = 0, values_per_point = 0, packed_step = 0;
};

// The header's lines up to DATA, every keyword checked against the others.
PcdHeader read_pcd_header(const std::string& path, LineTokenizer& lines) {
  PcdHeader header;
  std::vector<PcdField>& fields = header.fields;
  std::string_view& data = header.data;
  std::vector<std::string_view> tokens;
  bool has_fields = false, has_size = false, has_type = false;
  std::size_t width = 0, height = 0, points = 0;
  bool has_width = false, has_height = false, has_points = false;
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

  header.points = points;
  return header;
}

// Offsets of the fields in a point (binary), in a line (ascii) and the packed size of a point
// (binary_compressed leaves "_" padding out).
void lay_out(const std::string& path, PcdHeader& header) {
  std::size_t& point_step = header.point_step;
  std::size_t& values_per_point = header.values_per_point;
  std::size_t& packed_step = header.packed_step;
  for (PcdField& field : header.fields) {
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
}

// The x, y, z fields, normal_x, normal_y, normal_z when all three are there, and the density's
// field when one is asked for (null: not read).
struct PcdColumns {
  static constexpr int kCount = 7;
  const PcdField* fields[kCount] = {};
};

PcdColumns pcd_columns(const std::string& path, const std::vector<PcdField>& fields,
                       const std::string& density_field) {
  PcdColumns columns;
  const auto find = [&](std::string_view name) -> const PcdField* {
    for (const PcdField& field : fields)
      if (field.name == name) return &field;
    return nullptr;
  };
  const char* const kNames[6] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (int c = 0; c < 6; ++c) columns.fields[c] = find(kNames[c]);
  if (!columns.fields[0] || !columns.fields[1] || !columns.fields[2])
    fail(path, "PCD file has no x, y, z fields");
  if (!columns.fields[3] || !columns.fields[4] || !columns.fields[5])
    columns.fields[3] = columns.fields[4] = columns.fields[5] = nullptr;
  if (!density_field.empty()) {
    columns.fields[6] = find(density_field);
    if (!columns.fields[6]) {
      std::string names;
      for (const PcdField& field : fields)
        names += (names.empty() ? "" : " ") + std::string(field.name);
      fail(path, "no field " + quote(density_field) + " for the density (fields: " + names + ")");
    }
  }
  return columns;
}

void add_point(SurfaceInput& surface, const PcdColumns& columns,
               const double (&values)[PcdColumns::kCount]) {
  surface.points.emplace_back(values[0], values[1], values[2]);
  if (columns.fields[3]) surface.normals.emplace_back(values[3], values[4], values[5]);
  if (columns.fields[6]) surface.density.push_back(values[6]);
}

SurfaceInput read_pcd_ascii(const std::string& path, LineTokenizer rows, const PcdHeader& header,
                            const PcdColumns& columns) {
  SurfaceInput surface;
  std::vector<std::string_view> tokens;
  double values[PcdColumns::kCount] = {};
  while (rows.next(tokens)) {
    if (surface.points.size() == header.points)
      rows.fail("more points than POINTS " + std::to_string(header.points));
    if (tokens.size() != header.values_per_point)
      rows.fail("expected " + std::to_string(header.values_per_point) + " values, found " +
                std::to_string(tokens.size()));
    for (int c = 0; c < PcdColumns::kCount; ++c) {
      if (!columns.fields[c]) continue;
      const PcdField& field = *columns.fields[c];
      values[c] = rows.number(tokens[field.value]);
      // As if stored in the field's type, like the binary formats (and PCL)
      if (field.scalar == ScalarType::kFloat32) values[c] = static_cast<float>(values[c]);
    }
    add_point(surface, columns, values);
  }
  if (surface.points.size() < header.points)
    fail(path, "truncated: " + std::to_string(surface.points.size()) + " of " +
                   std::to_string(header.points) + " points");
  return surface;
}

// The points of binary data from `start`, the value of field f of point i at start + at(f, i).
template <typename Offset>
SurfaceInput read_pcd_values(const char* start, const PcdHeader& header,
                             const PcdColumns& columns, Offset&& at) {
  // PCL writes binary data in the host's order, which is little-endian everywhere it runs.
  const bool swap = !host_is_little_endian();
  SurfaceInput surface;
  double values[PcdColumns::kCount] = {};
  for (std::size_t i = 0; i < header.points; ++i) {
    for (int c = 0; c < PcdColumns::kCount; ++c) {
      if (!columns.fields[c]) continue;
      const PcdField& field = *columns.fields[c];
      const char* cursor = start + at(field, i);
      read_scalar(cursor, cursor + field.size, field.scalar, swap, values[c]);
    }
    add_point(surface, columns, values);
  }
  return surface;
}

SurfaceInput read_pcd_binary(const std::string& path, std::string_view body,
                             const PcdHeader& header, const PcdColumns& columns) {
  if (header.points > body.size() / header.point_step)
    fail(path, "truncated: PCD data of " + std::to_string(body.size()) + " bytes, too few for " +
                   std::to_string(header.points) + " points of " +
                   std::to_string(header.point_step) + " bytes");
  return read_pcd_values(body.data(), header, columns, [&](const PcdField& field, std::size_t i) {
    return i * header.point_step + field.offset;
  });
}

// Two 32-bit sizes, then LZF data that unpacks to one block per field (all points' values of the
// first field, then of the second, ...), "_" fields left out.
SurfaceInput read_pcd_compressed(const std::string& path, std::string_view body,
                                 PcdHeader& header, const PcdColumns& columns) {
  const std::size_t points = header.points, packed_step = header.packed_step;
  const bool swap = !host_is_little_endian();
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
  if (points == 0) return {};
  std::vector<char> unpacked(uncompressed);
  if (lzf_decompress(cursor, static_cast<unsigned>(compressed), unpacked.data(),
                     static_cast<unsigned>(uncompressed)) != uncompressed)
    fail(path,
         "corrupt: compressed data does not unpack to " + std::to_string(uncompressed) + " bytes");
  std::size_t start = 0;
  for (PcdField& field : header.fields) {
    field.block = start;
    if (field.name != "_") start += points * field.size * field.count;
  }
  return read_pcd_values(unpacked.data(), header, columns,
                         [&](const PcdField& field, std::size_t i) {
                           return field.block + i * field.size * field.count;
                         });
}

}  // namespace

SurfaceInput read_pcd(const std::string& path, const std::string& density_field) {
  const std::string bytes = read_file(path, ".pcd");
  LineTokenizer lines(path, bytes);
  PcdHeader header = read_pcd_header(path, lines);
  lay_out(path, header);
  const PcdColumns columns = pcd_columns(path, header.fields, density_field);
  const std::string_view body = std::string_view(bytes).substr(lines.position());
  if (header.data == "ascii")
    return read_pcd_ascii(path, LineTokenizer(path, body, lines.line()), header, columns);
  if (header.data == "binary") return read_pcd_binary(path, body, header, columns);
  return read_pcd_compressed(path, body, header, columns);
}

}  // namespace vmas::io_internal
