#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static int counter = 0;
    dir_ = fs::temp_directory_path() /
           ("vmas_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::string write(const std::string& name, const std::string& contents) const {
    std::ofstream(path(name), std::ios::binary) << contents;
    return path(name);
  }

  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

// Checks that `action` throws IoError with a one-line "PATH: ..." message mentioning `detail`.
void expect_io_error(const std::function<void()>& action, const std::string& path,
                     const std::string& detail) {
  try {
    action();
    ADD_FAILURE() << "no IoError for " << path;
  } catch (const IoError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(detail), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

SurfaceInput tetrahedron() {
  SurfaceInput mesh;
  mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

SurfaceInput random_cloud(int count, bool normals) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  SurfaceInput cloud;
  for (int i = 0; i < count; ++i) {
    cloud.points.push_back(test::draw_xyz([&] { return uniform(rng); }));
    if (normals) {
      const double x = uniform(rng);
      const double y = uniform(rng);
      cloud.normals.push_back(Vec3(x, y, 2.0).normalized());
    }
  }
  return cloud;
}

void expect_near(const std::vector<Vec3>& actual, const std::vector<Vec3>& expected,
                 double tolerance) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i)
    EXPECT_LE((actual[i] - expected[i]).norm(), tolerance) << "at " << i;
}

template <typename T>
void append_big_endian(std::string& out, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof value);
  std::reverse(raw, raw + sizeof raw);
  out.append(raw, sizeof raw);
}

// ---------------------------------------------------------------------------------------------
// Round trips

class IoRoundTrip : public IoTest {};

TEST_F(IoRoundTrip, MeshThroughPlyAndOff) {
  const SurfaceInput mesh = tetrahedron();
  for (const char* name : {"tet.ply", "tet.off", "TET.OFF"}) {
    write_surface(path(name), mesh);
    CleanReport report;
    const SurfaceInput read = read_surface(path(name), &report);
    expect_near(read.points, mesh.points, 1e-6);
    EXPECT_EQ(read.faces, mesh.faces) << name;
    EXPECT_FALSE(read.has_normals());
    EXPECT_EQ(report.total(), 0u);
  }
}

TEST_F(IoRoundTrip, CloudWithAndWithoutNormals) {
  for (bool normals : {false, true}) {
    const SurfaceInput cloud = random_cloud(200, normals);
    for (const char* name : {"c.ply", "c.off", "c.xyz"}) {
      write_surface(path(name), cloud);
      const SurfaceInput read = read_surface(path(name));
      EXPECT_FALSE(read.is_mesh());
      expect_near(read.points, cloud.points, 1e-6);
      EXPECT_EQ(read.has_normals(), normals) << name;
      if (normals) expect_near(read.normals, cloud.normals, 1e-6);
    }
  }
}

TEST_F(IoRoundTrip, OffIsExactForDoubles) {
  SurfaceInput cloud;
  cloud.points = {Vec3(0.1, 1.0 / 3.0, -2e-300), Vec3(1e17 + 8, M_PI, std::exp(1.0))};
  write_surface(path("exact.off"), cloud);
  EXPECT_EQ(read_surface(path("exact.off")).points, cloud.points);
}

TEST_F(IoRoundTrip, MedialMeshMaExactAndPlyFloat) {
  MedialMesh mesh;
  mesh.spheres = {
      {Vec3(0.1, 0.2, 0.3), 0.05}, {Vec3(1.0 / 3.0, 0, -1), 0.125}, {Vec3(0, 1, 0), 1e-3}};
  mesh.edges = {{0, 1}, {1, 2}, {0, 2}};
  mesh.faces = {{0, 1, 2}};
  write_medial_mesh(path("m.ma"), mesh);
  const MedialMesh exact = read_medial_mesh(path("m.ma"));
  ASSERT_EQ(exact.spheres.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(exact.spheres[i].center, mesh.spheres[i].center);
    EXPECT_EQ(exact.spheres[i].radius, mesh.spheres[i].radius);
  }
  EXPECT_EQ(exact.edges, mesh.edges);
  EXPECT_EQ(exact.faces, mesh.faces);

  write_medial_mesh(path("m.ply"), mesh);
  std::ifstream in(path("m.ply"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\ncomment generated by vmas " +
                       std::string(version()) + "\n"),
            std::string::npos);
  EXPECT_NE(bytes.find("property float radius\nelement edge 3\nproperty int vertex1\n"),
            std::string::npos);
  const MedialMesh approx = read_medial_mesh(path("m.ply"));
  ASSERT_EQ(approx.spheres.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE((approx.spheres[i].center - mesh.spheres[i].center).norm(), 1e-6);
    EXPECT_NEAR(approx.spheres[i].radius, mesh.spheres[i].radius, 1e-6);
  }
  EXPECT_EQ(approx.edges, mesh.edges);
  EXPECT_EQ(approx.faces, mesh.faces);
}

TEST_F(IoRoundTrip, LabelsOnePerLine) {
  write_labels(path("labels.txt"), {3, 0, -1, 12});
  std::ifstream in(path("labels.txt"));
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "3\n0\n-1\n12\n");
  EXPECT_EQ(entries(), std::vector<std::string>{"labels.txt"});
}

// ---------------------------------------------------------------------------------------------
// PLY

class IoPly : public IoTest {};

TEST_F(IoPly, AsciiWithUnknownListElementFirstAndQuad) {
  const std::string file =
      write("a.ply",
            "ply\r\nformat ascii 1.0\r\ncomment hello\r\n"
            "element range_grid 3\r\nproperty list uchar int vertex_indices\r\n"
            "element vertex 5\r\nproperty double y\r\nproperty uchar flag\r\n"
            "property float x\r\nproperty int z\r\n"
            "element face 2\r\nproperty list uchar uint vertex_index\r\n"
            "end_header\r\n"
            "0\r\n2 7 8\r\n1 0\r\n"
            "0 9 0 0\r\n0 9 1 0\r\n1 9 1 0\r\n1 9 0 0\r\n0.5 9 0.5 1\r\n"
            "4 0 1 2 3\r\n3 0 1 4\r\n");
  const SurfaceInput mesh = read_surface(file);
  ASSERT_EQ(mesh.points.size(), 5u);
  EXPECT_EQ(mesh.points[2], Vec3(1, 1, 0));
  EXPECT_EQ(mesh.points[4], Vec3(0.5, 0.5, 1));
  const std::vector<std::array<int, 3>> faces = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}};
  EXPECT_EQ(mesh.faces, faces);
}

TEST_F(IoPly, BinaryBigEndianWithNormalsAndSkippedElement) {
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\n"
      "element junk 2\nproperty short a\nproperty list int short b\n"
      "element vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
  for (int item = 0; item < 2; ++item) {
    append_big_endian<std::int16_t>(bytes, 5);
    append_big_endian<std::int32_t>(bytes, 2);
    append_big_endian<std::int16_t>(bytes, -1);
    append_big_endian<std::int16_t>(bytes, -2);
  }
  const double coordinates[3][3] = {{1.5, -2, 3}, {0.1, 0.2, 0.3}, {-7, 8, 1e-3}};
  for (const auto& point : coordinates) {
    for (double value : point) append_big_endian(bytes, value);
    for (float value : {0.0f, 0.0f, 2.0f}) append_big_endian(bytes, value);
  }
  const SurfaceInput cloud = read_surface(write("be.ply", bytes));
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.points[0], Vec3(1.5, -2, 3));
  EXPECT_EQ(cloud.points[1], Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(cloud.points[2], Vec3(-7, 8, 1e-3));
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[1], Vec3(0, 0, 1));  // renormalised
}

TEST_F(IoPly, EveryTruncationOfABinaryFileThrows) {
  write_surface(path("full.ply"), tetrahedron());
  std::ifstream in(path("full.ply"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t length = 1; length < bytes.size(); ++length) {
    const std::string file = write("cut.ply", bytes.substr(0, length));
    EXPECT_THROW(read_surface(file), IoError) << "cut at " << length;
  }
  const std::string header_end = "end_header\n";
  const std::size_t body = bytes.find(header_end) + header_end.size();
  const std::string file = write("cut.ply", bytes.substr(0, body + 20));
  expect_io_error([&] { read_surface(file); }, file, "truncated");
}

TEST_F(IoPly, MedialMeshAsciiAcceptsRadiusNamedR) {
  const std::string file = write("m.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                 "property float y\nproperty float z\nproperty float r\n"
                                 "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
                                 "end_header\n0 0 0 0.5\n1 0 0 0.25\n0 1\n");
  const MedialMesh mesh = read_medial_mesh(file);
  ASSERT_EQ(mesh.spheres.size(), 2u);
  EXPECT_EQ(mesh.spheres[1].radius, 0.25);
  ASSERT_EQ(mesh.edges.size(), 1u);
  EXPECT_EQ(mesh.edges[0], (std::array<int, 2>{0, 1}));
}

TEST_F(IoPly, MalformedFilesThrow) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\n";
  const std::string bad_index =
      write("i.ply", header +
                         "element face 1\nproperty list uchar int vertex_indices\n"
                         "end_header\n0 0 0\n1 0 0\n3 0 1 2\n");
  expect_io_error([&] { read_surface(bad_index); }, bad_index, "out of range");
  const std::string no_end = write("n.ply", header + "0 0 0\n");
  expect_io_error([&] { read_surface(no_end); }, no_end, "end_header");
  const std::string word = write("w.ply", header + "end_header\n0 0 0\n1 zero 0\n");
  expect_io_error([&] { read_surface(word); }, word, "line 9: non-numeric token 'zero'");
  const std::string not_ply = write("x.ply", "OFF\n1 0 0\n0 0 0\n");
  expect_io_error([&] { read_surface(not_ply); }, not_ply, "not a PLY file");
  const std::string no_radius = write("r.ply", header + "end_header\n0 0 0\n1 0 0\n");
  expect_io_error([&] { read_medial_mesh(no_radius); }, no_radius, "radius");
}

// ---------------------------------------------------------------------------------------------
// OFF, OBJ, XYZ

class IoOff : public IoTest {};

TEST_F(IoOff, CommentsBlankLinesQuadsAndColours) {
  const std::string file = write("q.off",
                                 "# a comment\n\nCOFF # trailing comment\n# counts next\n"
                                 "5 2 0\n0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n\n"
                                 "1 1 0 1 2 3 4\n0 1 0 0 0 0 0\n0 0 1 0 0 0 0\n"
                                 "4 0 1 2 3 # quad\n3 0 1 4\n");
  const SurfaceInput mesh = read_surface(file);
  ASSERT_EQ(mesh.points.size(), 5u);
  EXPECT_EQ(mesh.points[2], Vec3(1, 1, 0));
  EXPECT_FALSE(mesh.has_normals());
  const std::vector<std::array<int, 3>> faces = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}};
  EXPECT_EQ(mesh.faces, faces);
}

TEST_F(IoOff, NoffCloudWithNormalsAndMissingOnes) {
  const std::string file = write("n.off", "NOFF\n3 0\n0 0 0 0 0 3\n1 0 0 0 1 0\n2 0 0 1 0 0\n");
  const SurfaceInput cloud = read_surface(file);
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));
  EXPECT_EQ(cloud.normals[2], Vec3(1, 0, 0));

  // A point whose normal is missing while others have one keeps its place; its normal is NaN
  // until preparation estimates it.
  const std::string partial = write("p.off", "NOFF 3 0\n0 0 0 0 0 1\n1 0 0\n2 0 0 1 0 0\n");
  CleanReport report;
  const SurfaceInput kept = read_surface(partial, &report);
  EXPECT_EQ(kept.points.size(), 3u);
  EXPECT_EQ(report.non_finite_points, 0u);
  EXPECT_EQ(report.missing_normals, 1u);
  EXPECT_TRUE(std::isnan(kept.normals[1].x()));

  // NOFF without any normal (seen in real files) loads as a plain cloud.
  const std::string none = write("z.off", "NOFF\n2 0\n0 0 0\n1 0 0\n");
  EXPECT_FALSE(read_surface(none).has_normals());
}

TEST_F(IoOff, MalformedFilesThrow) {
  const std::string index = write("i.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  expect_io_error([&] { read_surface(index); }, index, "line 6: vertex index 3 out of range");
  const std::string truncated = write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  expect_io_error([&] { read_surface(truncated); }, truncated, "truncated");
  const std::string header = write("h.off", "PLY\n3 1 0\n");
  expect_io_error([&] { read_surface(header); }, header, "bad header");
  const std::string word = write("w.off", "OFF\n1 0 0\n0 0 abc\n");
  expect_io_error([&] { read_surface(word); }, word, "line 3: non-numeric token 'abc'");
  const std::string zero = write("e.off", "OFF\n0 0 0\n");
  expect_io_error([&] { read_surface(zero); }, zero, "no points");
}

class IoObj : public IoTest {};

TEST_F(IoObj, SlashFormsNegativeIndicesAndPolygons) {
  const std::string file = write("m.obj",
                                 "# cube corner\nmtllib x.mtl\no thing\n"
                                 "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                                 "f 1/1/1 2/1/1 3/1/1 4/1/1\nv 0 0 1\ns off\n"
                                 "f -5//1 -4//1 -1//1\nf 2/1 3/1 5/1\n");
  const SurfaceInput mesh = read_surface(file);
  ASSERT_EQ(mesh.points.size(), 5u);
  const std::vector<std::array<int, 3>> faces = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}, {1, 2, 4}};
  EXPECT_EQ(mesh.faces, faces);
  EXPECT_FALSE(mesh.has_normals());
}

TEST_F(IoObj, OrientedPointsAndErrors) {
  const std::string cloud_file = write("c.obj", "v 0 0 0\nv 1 0 0\nvn 0 0 2\nvn 0 1 0\nf\n");
  const SurfaceInput cloud = read_surface(cloud_file);
  ASSERT_EQ(cloud.points.size(), 2u);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));

  const std::string index = write("i.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expect_io_error([&] { read_surface(index); }, index, "line 4: vertex index 3 out of range");
  const std::string zero = write("z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expect_io_error([&] { read_surface(zero); }, zero, "index 0");
  const std::string before = write("b.obj", "v 0 0 0\nf -1 -2 -3\n");
  expect_io_error([&] { read_surface(before); }, before, "out of range");
}

class IoXyz : public IoTest {};

TEST_F(IoXyz, ColumnsSeparatorsAndErrors) {
  const std::string file = write("p.txt", "# x y z\n0,0,0\n\n1 2 3\n  4\t5 6  \r\n");
  const SurfaceInput cloud = read_surface(file);
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.points[2], Vec3(4, 5, 6));
  EXPECT_FALSE(cloud.has_normals());

  const std::string four = write("f.xyz", "0 0 0\n1 1 1\n1 2 3 4\n");
  expect_io_error([&] { read_surface(four); }, four, "line 3: expected 3 or 6 columns");
  const std::string word = write("w.xyz", "0 0 0\n1 one 1\n");
  expect_io_error([&] { read_surface(word); }, word, "line 2: non-numeric token 'one'");
  const std::string comments = write("c.xyz", "# nothing\n\n");
  expect_io_error([&] { read_surface(comments); }, comments, "no points");
}

// Variants seen in the wild: a leading count line, colour columns, decimal commas. None of them
// may be read as normals or as extra points.
TEST_F(IoXyz, CountLineColoursAndDecimalCommas) {
  const SurfaceInput counted = read_surface(write("n.xyz", "3\n0 0 0\n1 0 0\n0 1 0\n"));
  ASSERT_EQ(counted.points.size(), 3u);
  EXPECT_EQ(counted.points[0], Vec3(0, 0, 0));
  const std::string wrong = write("m.xyz", "4\n0 0 0\n1 0 0\n0 1 0\n");
  expect_io_error([&] { read_surface(wrong); }, wrong, "line 1 announces 4 points but 3 follow");

  const SurfaceInput coloured =
      read_surface(write("rgb.xyz", "0 0 0 255 0 0\n1 0 0 0 128 7\n0 1 0 1 1 1\n"));
  ASSERT_EQ(coloured.points.size(), 3u);
  EXPECT_FALSE(coloured.has_normals());
  const SurfaceInput with_normals =
      read_surface(write("nrm.xyz", "0 0 0 0 0 1\n1 0 0 1 0 0\n0 1 0 0 1 0\n"));
  EXPECT_TRUE(with_normals.has_normals());

  const SurfaceInput commas =
      read_surface(write("dc.xyz", "0,0094 -0,0241 0,9997\n1,5 0 0\n-2,25 1 0\n"));
  ASSERT_EQ(commas.points.size(), 3u);
  EXPECT_EQ(commas.points[0], Vec3(0.0094, -0.0241, 0.9997));
  EXPECT_EQ(commas.points[2], Vec3(-2.25, 1, 0));
  const SurfaceInput mixed = read_surface(write("mx.xyz", "0 0 0\n1,5 2,5 3,5\n0,5 0 1\n"));
  ASSERT_EQ(mixed.points.size(), 3u);
  EXPECT_EQ(mixed.points[1], Vec3(1.5, 2.5, 3.5));
  EXPECT_FALSE(mixed.has_normals());
  const SurfaceInput some_colours =
      read_surface(write("sc.xyz", "0 0 0\n1 0 0 255 0 0\n0 1 0 0 0 255\n"));
  EXPECT_FALSE(some_colours.has_normals());
  const SurfaceInput csv = read_surface(write("csv.xyz", "0.5,0.25,1\n1,2,3\n"));
  ASSERT_EQ(csv.points.size(), 2u);
  EXPECT_EQ(csv.points[1], Vec3(1, 2, 3));
}

// ---------------------------------------------------------------------------------------------
// PCD

class IoPcd : public IoTest {};

TEST_F(IoPcd, OrganizedCloudWithNanAndNormals) {
  const std::string file =
      write("o.pcd",
            "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
            "TYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\n"
            "POINTS 4\nDATA ascii\n0 0 0 0 0 1\nnan nan nan nan nan nan\n1 0 0 0 2 0\n"
            "2 0 0 0 0 0\n");
  CleanReport report;
  const SurfaceInput cloud = read_surface(file, &report);
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(report.non_finite_points, 1u);  // the NaN point; the zero normal's point stays
  EXPECT_EQ(report.missing_normals, 1u);
  EXPECT_EQ(cloud.normals[1], Vec3(0, 1, 0));
  EXPECT_TRUE(std::isnan(cloud.normals[2].x()));
}

TEST_F(IoPcd, XyzOnlyAndTruncatedBinary) {
  std::string bytes =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA binary\n";
  for (int i = 0; i < 3; ++i) {
    const float x = static_cast<float>(i), y = 0.5f;
    const double z = -1.0 / 3.0;
    bytes.append(reinterpret_cast<const char*>(&x), 4).append(reinterpret_cast<const char*>(&y), 4);
    bytes.append(reinterpret_cast<const char*>(&z), 8);
  }
  const SurfaceInput cloud = read_surface(write("b.pcd", bytes));
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.points[2], Vec3(2, 0.5, -1.0 / 3.0));
  EXPECT_FALSE(cloud.has_normals());

  const std::string truncated = write("t.pcd", bytes.substr(0, bytes.size() - 10));
  expect_io_error([&] { read_surface(truncated); }, truncated, "PCD");
}

// binary_compressed: LZF data unpacking to one block per field ("_" padding fields left out).
TEST_F(IoPcd, BinaryCompressedUnpacksFieldBlocks) {
  const std::string header =
      "VERSION 0.7\nFIELDS x _ y z normal_x normal_y normal_z\nSIZE 4 1 4 8 4 4 4\n"
      "TYPE F U F F F F F\nCOUNT 1 3 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n"
      "DATA binary_compressed\n";
  std::string blocks;
  const auto add = [&](auto first, auto second) {
    blocks.append(reinterpret_cast<const char*>(&first), sizeof first);
    blocks.append(reinterpret_cast<const char*>(&second), sizeof second);
  };
  add(1.0f, 2.0f);   // x
  add(3.0f, 4.0f);   // y
  add(-0.5, 0.25);   // z (double)
  add(0.0f, 0.0f);   // normal_x
  add(0.0f, 0.0f);   // normal_y
  add(1.0f, -2.0f);  // normal_z
  ASSERT_EQ(blocks.size(), 56u);
  // LZF: a literal run of n <= 32 bytes is the byte n - 1, then the bytes.
  std::string lzf = std::string(1, static_cast<char>(31)) + blocks.substr(0, 32) +
                    std::string(1, static_cast<char>(23)) + blocks.substr(32);
  const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(lzf.size()), 56};
  const std::string body = std::string(reinterpret_cast<const char*>(sizes), 8) + lzf;
  const SurfaceInput cloud = read_surface(write("c.pcd", header + body));
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[0], Vec3(1, 3, -0.5));
  EXPECT_EQ(cloud.points[1], Vec3(2, 4, 0.25));
  EXPECT_EQ(cloud.normals[1], Vec3(0, 0, -1));

  const std::string shorter = write("s.pcd", header + body.substr(0, body.size() - 1));
  expect_io_error([&] { read_surface(shorter); }, shorter, "truncated");
}

TEST_F(IoPcd, AsciiFloatFieldsRoundLikeBinary) {
  const SurfaceInput cloud = read_surface(
      write("a.pcd",
            "# comment\nVERSION .7\nFIELDS x y z rgb\nSIZE 4 4 8 4\nTYPE F F F U\nWIDTH 1\n"
            "HEIGHT 1\nPOINTS 1\nDATA ascii\n0.1 0.2 0.3 4294967295\n"));
  ASSERT_EQ(cloud.points.size(), 1u);
  EXPECT_EQ(cloud.points[0], Vec3(static_cast<float>(0.1), static_cast<float>(0.2), 0.3));
}

// ---------------------------------------------------------------------------------------------
// Cleaning

TEST(IoClean, CountsOnCraftedMesh) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SurfaceInput mesh;
  mesh.points = {Vec3(0, 0, 0),   Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0),   // 3 duplicates 1
                 Vec3(nan, 0, 0), Vec3(2, 0, 0), Vec3(5, 5, 5), Vec3(0, 0, 1)};  // 6 unused
  mesh.faces = {{0, 1, 2},                                                       // kept
                {0, 3, 7},   // kept, remapped to {0, 1, 7}
                {0, 4, 2},   // references the NaN point
                {0, 1, 5},   // collinear: zero area
                {1, 3, 2}};  // repeated vertex after merging
  const CleanReport report = clean_surface(mesh);
  EXPECT_EQ(report.non_finite_points, 1u);
  EXPECT_EQ(report.duplicate_points, 1u);
  EXPECT_EQ(report.degenerate_faces, 3u);
  EXPECT_EQ(report.unused_points, 2u);  // (2,0,0) lost its face, (5,5,5) never had one
  EXPECT_EQ(report.total(), 7u);
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  EXPECT_EQ(mesh.points, points);
  const std::vector<std::array<int, 3>> faces = {{0, 1, 2}, {0, 1, 3}};
  EXPECT_EQ(mesh.faces, faces);
  EXPECT_EQ(report.kept, (std::vector<int>{0, 1, 2, 7}));
}

TEST(IoClean, RejectsInfiniteAndOverflowingCoordinates) {
  for (const double bad : {std::numeric_limits<double>::infinity(), -2e150}) {
    SurfaceInput cloud;
    cloud.points = {Vec3(0, 0, 0), Vec3(1, bad, 0)};
    try {
      clean_surface(cloud);
      ADD_FAILURE() << "no InvalidInput for " << bad;
    } catch (const InvalidInput& error) {
      EXPECT_NE(std::string(error.what()).find("point 1: coordinate"), std::string::npos)
          << error.what();
    }
  }
  SurfaceInput edge;
  edge.points = {Vec3(0, 0, 0), Vec3(1e150, -1e150, 1)};
  EXPECT_EQ(clean_surface(edge).total(), 0u);
}

TEST(IoClean, CleaningTwiceChangesNothing) {
  // Normals of arbitrary length, normalised once; a second pass must keep every bit.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  SurfaceInput cloud;
  for (int i = 0; i < 2000; ++i) {
    cloud.points.push_back(Vec3(i, 0.5 * i, 0.25 * i));
    cloud.normals.push_back(3.7 * Vec3(uniform(rng), uniform(rng), uniform(rng)));
  }
  clean_surface(cloud);
  const SurfaceInput once = cloud;
  const CleanReport again = clean_surface(cloud);
  EXPECT_EQ(again.total(), 0u);
  EXPECT_EQ(cloud.points, once.points);
  EXPECT_EQ(cloud.normals, once.normals);
}

TEST(IoClean, CloudKeepsFirstDuplicateAndOrderAndPointsWithoutNormals) {
  SurfaceInput cloud;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  cloud.points = {Vec3(3, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 0),
                  Vec3(nan, 0, 0)};
  cloud.normals = {Vec3(0, 0, 2), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 0),
                   Vec3(0, std::numeric_limits<double>::infinity(), 0), Vec3(1, 0, 0)};
  const CleanReport report = clean_surface(cloud);
  EXPECT_EQ(report.non_finite_points, 1u);
  EXPECT_EQ(report.missing_normals, 2u);
  EXPECT_EQ(report.duplicate_points, 1u);
  EXPECT_EQ(report.unused_points, 0u);
  const std::vector<Vec3> points = {Vec3(3, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 0)};
  EXPECT_EQ(cloud.points, points);
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));
  EXPECT_EQ(cloud.normals[1], Vec3(0, 1, 0));
  EXPECT_TRUE(std::isnan(cloud.normals[2].x()) && std::isnan(cloud.normals[3].x()));
  EXPECT_EQ(report.kept, (std::vector<int>{0, 1, 3, 4}));
}

// ---------------------------------------------------------------------------------------------
// Errors common to every format, and atomic writes

class IoErrors : public IoTest {};

TEST_F(IoErrors, PathProblems) {
  const std::string missing = path("missing.off");
  expect_io_error([&] { read_surface(missing); }, missing, "no such file");
  expect_io_error([&] { read_medial_mesh(path("missing.ma")); }, path("missing.ma"),
                  "no such file");
  fs::create_directory(path("folder.ply"));
  expect_io_error([&] { read_surface(path("folder.ply")); }, path("folder.ply"), "directory");
  const std::string unknown = write("shape.stl", "solid\n");
  expect_io_error([&] { read_surface(unknown); }, unknown, "unknown file extension '.stl'");
  for (const char* name : {"e.off", "e.ply", "e.obj", "e.xyz", "e.pcd", "e.ma"}) {
    const std::string empty = write(name, "");
    const auto read = [&] {
      if (fs::path(empty).extension() == ".ma")
        read_medial_mesh(empty);
      else
        read_surface(empty);
    };
    expect_io_error(read, empty, "empty file");
  }
}

TEST_F(IoErrors, MaValidation) {
  const std::string count = write("c.ma", "2 1 0\nv 0 0 0 1\ne 0 1\n");
  expect_io_error([&] { read_medial_mesh(count); }, count, "2 vertices but 1 were found");
  const std::string index = write("i.ma", "2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 2\n");
  expect_io_error([&] { read_medial_mesh(index); }, index, "line 4: vertex index 2 out of range");
  const std::string record = write("r.ma", "1 0 0\nv 0 0 0 1\nq 1\n");
  expect_io_error([&] { read_medial_mesh(record); }, record, "unknown record 'q'");
  const std::string extra = write("x.ma", "# made by hand\n1 0 0 extra\nv 0 0 0 1 99\n");
  EXPECT_EQ(read_medial_mesh(extra).spheres.size(), 1u);
}

TEST_F(IoErrors, AtomicWritesLeaveNothingBehind) {
  fs::create_directory(path("out.ply"));
  expect_io_error([&] { write_surface(path("out.ply"), tetrahedron()); }, path("out.ply"),
                  "cannot write");
  expect_io_error([&] { write_file_atomically(path("out.ply"), "x"); }, path("out.ply"),
                  "cannot write");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.ply"});
  EXPECT_TRUE(fs::is_empty(path("out.ply")));

  // A folder that exists but takes no new file (even for root).
  const std::string unwritable = "/proc/vmas_test_output.ply";
  expect_io_error([&] { check_medial_mesh_output(unwritable); }, unwritable,
                  "cannot write in folder '/proc'");
  check_output(path("fine.txt"));  // leaves nothing behind

  const std::string nowhere = path("no/such/dir/m.ma");
  expect_io_error([&] { write_medial_mesh(nowhere, MedialMesh{}); }, nowhere, "cannot write");
  expect_io_error([&] { write_labels(nowhere, {1}); }, nowhere, "cannot write");
  expect_io_error([&] { write_medial_mesh(path("m.obj"), MedialMesh{}); }, path("m.obj"), "'.obj'");
  expect_io_error([&] { write_surface(path("m.stl"), tetrahedron()); }, path("m.stl"), "'.stl'");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.ply"});

  // Overwriting replaces the whole file.
  write_file_atomically(path("a.txt"), "long contents\n");
  write_file_atomically(path("a.txt"), "short\n");
  std::ifstream in(path("a.txt"));
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "short\n");
}

// Randomly corrupted files must load or throw IoError: never crash, hang or throw anything else.
TEST_F(IoErrors, CorruptedFilesLoadOrThrowIoError) {
  SurfaceInput cloud = random_cloud(20, true);
  write_surface(path("c.ply"), cloud);
  write_surface(path("c.off"), cloud);
  write_surface(path("t.ply"), tetrahedron());
  write_surface(path("t.off"), tetrahedron());
  MedialMesh medial;
  medial.spheres = {{Vec3(0, 0, 0), 1}, {Vec3(1, 0, 0), 1}, {Vec3(0, 1, 0), 1}};
  medial.edges = {{0, 1}, {1, 2}, {2, 0}};
  medial.faces = {{0, 1, 2}};
  write_medial_mesh(path("m.ply"), medial);
  write_medial_mesh(path("m.ma"), medial);
  write("a.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 2 3\n");
  write("o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1/1/1 2//2 3 4\nf -1 -2 -3\n");
  const char kSpecial[] = {'0', '9', '-', ' ', '\n', '#', '/', 'e', '\0', '\xff'};
  std::mt19937 rng(11);
  for (const char* name : {"c.ply", "c.off", "t.ply", "t.off", "m.ply", "m.ma", "a.ply", "o.obj"}) {
    std::ifstream in(path(name), std::ios::binary);
    const std::string original((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    const std::string corrupt = path(std::string("x") + fs::path(name).extension().string());
    for (int trial = 0; trial < 300; ++trial) {
      std::string bytes = original;
      for (int change = 0; change < 1 + trial % 4; ++change) {
        const std::size_t at = rng() % bytes.size();
        bytes[at] = rng() % 2 ? kSpecial[rng() % sizeof kSpecial] : static_cast<char>(rng());
      }
      if (trial % 5 == 0) bytes.resize(rng() % bytes.size() + 1);
      std::ofstream(corrupt, std::ios::binary | std::ios::trunc) << bytes;
      try {
        if (fs::path(name).stem() == "m")
          read_medial_mesh(corrupt);
        else
          read_surface(corrupt);
      } catch (const IoError&) {
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Real files

class IoRealData : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::is_directory(VMAS_SHARED_DATA))
      GTEST_SKIP() << "shared data not found at " << VMAS_SHARED_DATA;
  }
  static std::string data(const std::string& name) {
    return (fs::path(VMAS_SHARED_DATA) / name).string();
  }
};

TEST_F(IoRealData, Scans) {
  struct Expected {
    const char* name;
    std::size_t points;
    bool normals;
  };
  const Expected scans[] = {{"scans/bunny_merged_45k.xyz", 45284, false},
                            {"scans/bunny_range_bun000.ply", 40256, false},
                            {"scans/bunny_397_normals.pcd", 397, true},
                            {"scans/milk_single_view.pcd", 13704, false},
                            {"scans/car6_lidar.pcd", 10031, false},
                            {"scans/tum_rabbit_normals.xyz", 10429, true},
                            {"scans/woman_oriented_points.off", 11798, true},
                            {"scans/misaligned_views_normals.off", 15002, false},
                            {"scans/ant_oriented_points.obj", 3000, true}};
  for (const Expected& scan : scans) {
    CleanReport report;
    const SurfaceInput cloud = read_surface(data(scan.name), &report);
    std::cout << scan.name << ": " << cloud.points.size() << " points, normals "
              << cloud.has_normals() << "; dropped " << report.non_finite_points
              << " non-finite, merged " << report.duplicate_points << " duplicates\n";
    EXPECT_FALSE(cloud.is_mesh()) << scan.name;
    EXPECT_EQ(cloud.has_normals(), scan.normals) << scan.name;
    EXPECT_EQ(cloud.points.size() + report.total(), scan.points) << scan.name;
    EXPECT_GT(cloud.points.size(), scan.points * 9 / 10) << scan.name;
    if (cloud.has_normals()) {
      ASSERT_EQ(cloud.normals.size(), cloud.points.size());
      for (const Vec3& normal : cloud.normals) ASSERT_NEAR(normal.norm(), 1.0, 1e-9);
    }
  }
}

TEST_F(IoRealData, Meshes) {
  for (const auto& [name, vertices] :
       {std::pair<const char*, std::size_t>{"meshes/bear.off", 10141}, {"meshes/dove.off", 5519}}) {
    CleanReport report;
    const SurfaceInput mesh = read_surface(data(name), &report);
    std::cout << name << ": " << mesh.points.size() << " vertices, " << mesh.faces.size()
              << " faces; cleaned " << report.total() << "\n";
    ASSERT_TRUE(mesh.is_mesh());
    EXPECT_EQ(report.total(), 0u) << name;
    EXPECT_EQ(mesh.points.size(), vertices) << name;
    // A closed triangle mesh: F = 2V - 4 + 4g, so at least 2V - 4 faces.
    EXPECT_GE(mesh.faces.size() + 4, 2 * mesh.points.size()) << name;
  }
}

TEST_F(IoRealData, ReferenceMedialMeshes) {
  int files = 0;
  for (const auto& model : fs::directory_iterator(data("reference")))
    for (const auto& file : fs::directory_iterator(model.path())) {
      if (file.path().extension() != ".ma") continue;
      const MedialMesh mesh = read_medial_mesh(file.path().string());
      EXPECT_GT(mesh.spheres.size(), 10u) << file.path();
      EXPECT_GT(mesh.edges.size(), mesh.faces.size()) << file.path();
      for (const Sphere& sphere : mesh.spheres) EXPECT_GT(sphere.radius, 0.0) << file.path();
      ++files;
    }
  EXPECT_EQ(files, 36);
}

}  // namespace
}  // namespace vmas
