// `vmas convert`: any format vmas reads, written as the cleaned shape (or medial mesh) it reads.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

class Convert : public test::CliTest {
 protected:
  // Runs `vmas convert ARGUMENTS`; returns the exit code, stderr in err_.
  int convert(const std::string& arguments) {
    last_ = run("convert " + arguments);
    err_ = last_.err;
    return last_.exit_code;
  }

  void expect_one_line_error(const std::string& what) const {
    test::expect_one_line_error(last_, what);
  }

  test::CliResult last_;
  std::string err_;
};

TEST_F(Convert, PcdCloudToOffGivesThePointsReadSurfaceReads) {
  // ASCII PCD with normals, one NaN point (dropped) and one duplicate (merged).
  std::ofstream(path("cloud.pcd"))
      << "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
         "TYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 5\nHEIGHT 1\nPOINTS 5\nDATA ascii\n"
         "0 0 0 0 0 1\n1.5 0 0 1 0 0\nnan nan nan 0 0 1\n0 2.25 0 0 1 0\n1.5 0 0 1 0 0\n";
  ASSERT_EQ(convert(path("cloud.pcd") + " " + path("cloud.off")), 0) << err_;
  const SurfaceInput read = read_surface(path("cloud.pcd"));
  const SurfaceInput converted = read_surface(path("cloud.off"));
  ASSERT_EQ(read.points.size(), 3u);
  EXPECT_EQ(converted.points, read.points);  // .off keeps doubles exactly
  EXPECT_EQ(converted.normals, read.normals);
  EXPECT_FALSE(converted.is_mesh());
}

TEST_F(Convert, MedialPlyToMaRoundTrip) {
  MedialMesh medial;
  medial.spheres = {{Vec3(0, 0, 0), 0.5}, {Vec3(1, 0, 0), 0.25}, {Vec3(0, 1, 0.5), 0.125}};
  medial.edges = {{0, 1}, {1, 2}, {2, 0}};
  medial.faces = {{0, 1, 2}};
  write_medial_mesh(path("m.ply"), medial);
  ASSERT_EQ(convert("--medial " + path("m.ply") + " " + path("m.ma")), 0) << err_;
  const MedialMesh ma = read_medial_mesh(path("m.ma"));
  ASSERT_EQ(ma.spheres.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {  // values exact in float, so exact after the trip
    EXPECT_EQ(ma.spheres[i].center, medial.spheres[i].center);
    EXPECT_EQ(ma.spheres[i].radius, medial.spheres[i].radius);
  }
  EXPECT_EQ(ma.edges, medial.edges);
  EXPECT_EQ(ma.faces, medial.faces);
  ASSERT_EQ(convert("--medial " + path("m.ma") + " " + path("back.ply")), 0) << err_;
  EXPECT_EQ(read_medial_mesh(path("back.ply")).faces, medial.faces);
}

TEST_F(Convert, ErrorsAreOneLineWithTheirExitCode) {
  EXPECT_EQ(convert(path("missing.pcd") + " " + path("out.off")), 1);
  expect_one_line_error(path("missing.pcd"));
  EXPECT_FALSE(fs::exists(path("out.off")));

  std::ofstream(path("cloud.xyz")) << "0 0 0\n1 0 0\n0 1 0\n";
  // An output format with no writer is a usage error, as in skeletonize (before any reading).
  EXPECT_EQ(convert(path("cloud.xyz") + " " + path("out.stl")), 2);
  expect_one_line_error(".stl");
  EXPECT_EQ(convert(path("cloud.xyz") + " " + path("cloud.abc") + " --medial"), 2);
  expect_one_line_error(".abc");
  EXPECT_EQ(convert(path("cloud.abc") + " " + path("out.off")), 1);  // no such reader
  expect_one_line_error(path("cloud.abc"));

  EXPECT_EQ(convert(path("cloud.xyz")), 2);  // no OUTPUT
  expect_one_line_error("OUTPUT");
  EXPECT_EQ(convert("--bogus " + path("cloud.xyz") + " " + path("out.off")), 2);
  expect_one_line_error("bogus");
  EXPECT_EQ(convert("--help"), 0);
}

}  // namespace
}  // namespace vmas
