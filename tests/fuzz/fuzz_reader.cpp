// libFuzzer target: the input bytes become a file of one format (VMAS_FUZZ_EXTENSION, set by
// CMake: one executable per format), which is read; a shape of at least 20 points then gets a
// tiny bounded skeletonization. Aborts when a promise is broken: a reader throwing anything but
// a one-line IoError naming the file, a non-finite sphere, an index out of range. Run by
// scripts/fuzz.
#include <omp.h>
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
#include "vmas/prepare.hpp"
#include "vmas/skeletonizer.hpp"

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

void skeletonize(vmas::SurfaceInput input) {
  try {
    // As the CLI does: outliers, noise, normals, then the run.
    const vmas::PrepareReport prepared = vmas::prepare_surface(input, {});
    vmas::SkeletonizerOptions options;
    options.target_spheres = 4;
    options.max_iterations = 20;
    vmas::adapt_shrinking_ball(prepared, options.shrinking_ball);
    vmas::Skeletonizer skeletonizer(vmas::build_shape(input, {}), options);
    skeletonizer.run();
    const vmas::MedialMesh mesh = prepared.frame.to_input(skeletonizer.medial_mesh());
    check(mesh.spheres.size() <= 4, "more spheres than asked");
    check_medial_mesh(mesh);
    for (const vmas::Sphere& sphere : mesh.spheres) check(sphere.radius >= 0.0, "negative radius");
    check(skeletonizer.labels().size() == skeletonizer.shape().points.size(),
          "not one label per vertex");
    for (int label : skeletonizer.labels())
      check(label >= 0 && static_cast<std::size_t>(label) < mesh.spheres.size(),
            "label out of range");
  } catch (const vmas::Error& error) {
    check(std::string(error.what()).find('\n') == std::string::npos,
          "error of more than one line:", error.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  omp_set_num_threads(1);  // the machine is shared; results do not depend on it
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
    if (input.points.size() >= 20) skeletonize(std::move(input));
  } catch (const vmas::IoError& error) {
    check_error_names_file(error);
  }
  return 0;
}
