// The IO stage's reading dispatcher: chooses the reader by extension, then cleans the shape.
#include "vmas/io.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/internal.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace io_internal {
namespace {

// Fails with a clear message for the usual reasons a path cannot be read.
void check_readable(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "no such file");
  if (std::filesystem::is_directory(status)) fail(path, "is a directory");
  // A FIFO, device or socket would block or never end: refused at once.
  if (!std::filesystem::is_regular_file(status))
    fail(path, "is not a regular file (" + io_internal::file_kind(status.type()) +
                   "); vmas reads regular files only");
  if (std::filesystem::file_size(path, error) == 0 && !error) fail(path, "empty file");
}

}  // namespace

// Bytes read first to tell whether the file can be of its format at all.
constexpr std::size_t kSniffedBytes = 4096;

std::string read_file(const std::string& path, const std::string& extension) {
  check_readable(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::string start(kSniffedBytes, '\0');
  in.read(start.data(), static_cast<std::streamsize>(start.size()));
  if (in.bad()) fail(path, "read error");
  start.resize(static_cast<std::size_t>(in.gcount()));
  if (extension == ".ply") {
    check_ply_start(path, start);
  } else {
    // A PCD's header is text up to its DATA line.
    const std::size_t text_end = extension == ".pcd" ? start.find("DATA") : std::string::npos;
    if (const std::size_t nul = start.substr(0, text_end).find('\0'); nul != std::string::npos)
      fail(path, "binary data where text is expected (a NUL byte at offset " +
                     std::to_string(nul) + ")");
  }
  in.clear();
  in.seekg(0);
  std::string bytes(std::filesystem::file_size(path), '\0');  // no regrowth: 1x the file
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) fail(path, "read error");
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (bytes.empty()) fail(path, "empty file");
  return bytes;
}

}  // namespace io_internal

using io_internal::fail;
using io_internal::lower_extension;
using io_internal::quote;
using io_internal::read_file;

namespace {

// Runs `read`; running out of memory is an IoError naming the file, as every reader's error is.
template <class Read>
auto naming_the_file_on_bad_alloc(const std::string& path, Read read) {
  try {
    return read();
  } catch (const std::bad_alloc&) {
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    fail(path, "not enough memory to read it (" + std::to_string(error ? 0 : bytes >> 20) +
                   " MB on disk)");
  }
}

SurfaceInput read_stored(const std::string& path, const std::string& density_field) {
  const std::string extension = lower_extension(path);
  if (!density_field.empty() && (extension == ".off" || extension == ".obj"))
    fail(path, "an " + extension.substr(1) +
                   " file holds no per-point values besides coordinates and normals: give the "
                   "density in a file of its own");
  SurfaceInput surface;
  if (extension == ".pcd") {
    surface = io_internal::read_pcd(path, density_field);
  } else if (extension == ".off" || extension == ".ply" || extension == ".obj" ||
             extension == ".xyz" || extension == ".txt") {
    const std::string bytes = read_file(path, extension);
    if (extension == ".off")
      surface = io_internal::parse_off(path, bytes);
    else if (extension == ".ply")
      surface = io_internal::parse_ply_surface(path, bytes, density_field);
    else if (extension == ".obj")
      surface = io_internal::parse_obj(path, bytes);
    else
      surface = io_internal::parse_xyz(path, bytes, density_field);
  } else {
    fail(path, "unknown file extension " + quote(extension) +
                   " (expected .off, .ply, .obj, .xyz, .txt or .pcd)");
  }
  if (surface.points.empty()) fail(path, "no points");
  return surface;
}

}  // namespace

SurfaceInput read_surface_as_stored(const std::string& path, const std::string& density_field) {
  // "No such file" beats "unknown extension" for a mistyped path.
  io_internal::check_readable(path);
  return naming_the_file_on_bad_alloc(path, [&] { return read_stored(path, density_field); });
}

std::vector<double> parse_density(const std::string& name, const std::string& text,
                                  std::size_t points) {
  io_internal::LineTokenizer lines(name, text);
  std::vector<std::string_view> tokens;
  std::vector<double> density;
  while (lines.next(tokens)) {
    if (tokens.size() != 1)
      lines.fail("expected one density value per line, found " + std::to_string(tokens.size()));
    if (density.size() == points)
      lines.fail("more values than the input's " + std::to_string(points) + " points");
    density.push_back(lines.number(tokens[0]));
  }
  if (density.size() != points)
    fail(name, std::to_string(density.size()) + " density values for the input's " +
                   std::to_string(points) + " points");
  return density;
}

std::vector<double> read_density(const std::string& path, std::size_t points) {
  io_internal::check_readable(path);
  return naming_the_file_on_bad_alloc(
      path, [&] { return parse_density(path, read_file(path, ""), points); });
}

SurfaceInput read_surface(const std::string& path, CleanReport* report) {
  SurfaceInput surface = read_surface_as_stored(path);
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

MedialMesh read_medial_mesh(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension != ".ma" && extension != ".ply")
    fail(path, "unknown medial mesh extension " + quote(extension) + " (expected .ply or .ma)");
  return naming_the_file_on_bad_alloc(path, [&] {
    const std::string bytes = read_file(path, extension);
    return extension == ".ma" ? io_internal::parse_ma(path, bytes)
                              : io_internal::parse_ply_medial(path, bytes);
  });
}

}  // namespace vmas
