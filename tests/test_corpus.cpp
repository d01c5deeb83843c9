// tests/corpus holds small hostile files: malformed headers, headers announcing far more data
// than the file holds, truncations, huge or non-finite values, and inputs that once crashed a
// fuzzer (tests/fuzz); plus small valid shapes (seed_*) that seed the fuzzers. Each must load
// sanely or fail with one IoError line naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "vmas/error.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> corpus_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(VMAS_SOURCE_DIR) / "tests" / "corpus"))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

bool in_range(const Vec3& v) { return (v.array().abs() <= 1e150).all(); }

void expect_sane(const SurfaceInput& surface) {
  ASSERT_FALSE(surface.points.empty());
  for (const Vec3& p : surface.points) EXPECT_TRUE(in_range(p)) << p.transpose();
  if (surface.has_normals()) {
    ASSERT_EQ(surface.normals.size(), surface.points.size());
    for (const Vec3& n : surface.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-9);
  }
  const int count = static_cast<int>(surface.points.size());
  for (const auto& face : surface.faces)
    for (int v : face) EXPECT_TRUE(v >= 0 && v < count) << v;
}

void expect_sane(const MedialMesh& mesh) {
  const int count = static_cast<int>(mesh.spheres.size());
  for (const Sphere& s : mesh.spheres) EXPECT_TRUE(in_range(s.center) && std::isfinite(s.radius));
  for (const auto& edge : mesh.edges)
    for (int v : edge) EXPECT_TRUE(v >= 0 && v < count) << v;
  for (const auto& face : mesh.faces)
    for (int v : face) EXPECT_TRUE(v >= 0 && v < count) << v;
}

TEST(Corpus, EveryFileLoadsSanelyOrFailsWithOneLineNamingIt) {
  // The hand-made files must fail, and say why; fuzzer finds need only behave.
  const std::map<std::string, std::string> expected = {
      {"pcd_one_byte.pcd", "unknown keyword 'x'"},
      {"pcd_two_hashes.pcd", "no DATA line"},
      {"pcd_version_only.pcd", "no DATA line"},
      {"pcd_no_data_line.pcd", "no DATA line"},
      {"pcd_points_bomb_binary.pcd", "truncated"},
      {"pcd_points_bomb_compressed.pcd", "uncompressed bytes for 1000000000 points"},
      {"pcd_lzf_ratio_bomb.pcd", "cannot hold"},
      {"pcd_lzf_empty.pcd", "cannot hold"},
      {"pcd_lzf_garbage.pcd", "does not unpack"},
      {"pcd_width_height_mismatch.pcd", "is not POINTS"},
      {"pcd_size_count_mismatch.pcd", "2 SIZE entries for 3 fields"},
      {"pcd_truncated_ascii.pcd", "truncated: 2 of 4 points"},
      {"pcd_huge_count.pcd", "COUNT"},
      {"pcd_half_float.pcd", "unsupported TYPE"},
      {"pcd_huge_coordinate.pcd", "out of range"},
      {"ply_vertex_bomb.ply", "truncated"},
      {"ply_face_bomb_binary.ply", "truncated"},
      {"ply_list_bomb_binary.ply", "truncated"},
      {"ply_truncated.ply", "truncated"},
      {"ply_huge_coordinate.ply", "out of range"},
      {"ply_infinite_coordinate.ply", "coordinate inf out of range"},
      {"off_vertex_bomb.off", "truncated"},
      {"off_face_bomb.off", "truncated"},
      {"off_polygon_bomb.off", "fewer indices"},
      {"off_truncated.off", "fewer indices"},
      {"off_huge_coordinate.off", "out of range"},
      {"obj_truncated.obj", "expected 3 coordinates"},
      {"obj_infinite_coordinate.obj", "out of range"},
      {"obj_index_overflow.obj", "out of range"},
      {"xyz_all_nan.xyz", "no usable points"},
      {"xyz_huge_coordinate.xyz", "out of range"},
      {"xyz_overflowing_number.xyz", "out of range"},
      {"ma_bomb.ma", "announces 2147483648 vertices but 1 were found"},
      {"ma_huge_sphere.ma", "sphere out of range"},
      {"ma_nan_radius.ma", "sphere out of range"}};
  const std::vector<fs::path> files = corpus_files();
  std::size_t found = 0;
  for (const fs::path& file : files) {
    const std::string path = file.string();
    SCOPED_TRACE(path);
    const auto known = expected.find(file.filename().string());
    found += known != expected.end();
    try {
      if (file.extension() == ".ma")
        expect_sane(read_medial_mesh(path));
      else
        expect_sane(read_surface(path));
      EXPECT_EQ(known, expected.end()) << "loaded";
    } catch (const IoError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      if (known != expected.end())
        EXPECT_NE(message.find(known->second), std::string::npos) << message;
    }
  }
  EXPECT_EQ(found, expected.size()) << "a listed file is missing from tests/corpus";
}

}  // namespace
}  // namespace vmas
