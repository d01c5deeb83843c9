// libFuzzer target: the input bytes become a file of one format (VMAS_FUZZ_EXTENSION, set by
// CMake: one executable per format), which is read; a shape of at least 20 usable points then
// gets a tiny bounded vmas::skeletonize, as the CLI runs it. Aborts when a promise is broken: a
// reader throwing anything but a one-line IoError naming the file, a count not met without an
// error, a non-finite sphere, an index out of range, labels not one per input point. Run by
// scripts/fuzz.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "vmas/error.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace {

void check(bool promise, const char* what, const std::string& detail = "") {
  if (promise) return;
  std::fprintf(stderr, "broken promise: %s %s\n", what, detail.c_str());
  std::abort();
}

const std::string& input_path() {
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("vmas_fuzz_" + std::to_string(::getpid()) + VMAS_FUZZ_EXTENSION))
          .string();
  return path;
}

void check_error_names_file(const vmas::Error& error) {
  const std::string message = error.what();
  check(message.rfind(input_path() + ": ", 0) == 0, "error does not start with the path:", message);
  check(message.find('\n') == std::string::npos, "error of more than one line:", message);
}

bool finite(const vmas::Vec3& v) { return v.allFinite(); }

template <typename Indices>
void check_indices(const Indices& items, std::size_t count, const char* what) {
  for (const auto& item : items)
    for (int v : item) check(v >= 0 && static_cast<std::size_t>(v) < count, what);
}

void check_medial_mesh(const vmas::MedialMesh& mesh) {
  for (const vmas::Sphere& sphere : mesh.spheres)
    check(finite(sphere.center) && std::isfinite(sphere.radius), "non-finite sphere");
  check_indices(mesh.edges, mesh.spheres.size(), "edge index out of range");
  check_indices(mesh.faces, mesh.spheres.size(), "face index out of range");
}

// The one call the CLI makes, bounded: the file as stored (NaN points and all), 4 spheres.
void skeletonize_bounded(const vmas::SurfaceInput& input) {
  try {
    vmas::Options options;
    options.run.target.spheres = 4;
    options.threads = 1;  // the machine is shared; results do not depend on it
    options.run.max_iterations = 20;
    const vmas::Result result = vmas::skeletonize(input, options);
    const vmas::MedialMesh& mesh = result.medial_mesh;
    check(mesh.spheres.size() == 4, "not the sphere count asked for");
    check_medial_mesh(mesh);
    for (const vmas::Sphere& sphere : mesh.spheres) check(sphere.radius >= 0.0, "negative radius");
    check(result.labels.size() == input.points.size(), "not one label per input point");
    for (int label : result.labels)
      check(label >= -1 && label < static_cast<int>(mesh.spheres.size()), "label out of range");
  } catch (const vmas::Error& error) {
    check(std::string(error.what()).find('\n') == std::string::npos,
          "error of more than one line:", error.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  input_path();  // constructed first, so destroyed after the handler below has run
  std::atexit([] { std::filesystem::remove(input_path()); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::ofstream(input_path(), std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  const std::string extension = VMAS_FUZZ_EXTENSION;
  try {
    if (extension == ".ma") {
      check_medial_mesh(vmas::read_medial_mesh(input_path()));
      return 0;
    }
    vmas::SurfaceInput input = vmas::read_surface(input_path());
    check(!input.points.empty(), "read_surface returned no points");
    for (const vmas::Vec3& p : input.points)
      check(finite(p) && (p.array().abs() <= 1e150).all(), "point out of range");
    check(!input.has_normals() || input.normals.size() == input.points.size(),
          "not one normal per point");
    check_indices(input.faces, input.points.size(), "face index out of range");
    // The CLI's way: the file as stored, cleaned inside the one call.
    if (input.points.size() >= 20) skeletonize_bounded(vmas::read_surface_as_stored(input_path()));
  } catch (const vmas::IoError& error) {
    check_error_names_file(error);
  }
  return 0;
}
