// Density fields (SurfaceInput::density): where spheres go, what a uniform field changes (nothing),
// how it follows the points through preparation, and the errors of bad fields.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cli_fixture.hpp"
#include "prepare/prepare.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

// An elongated ellipsoid cloud with its exact normals; its end beyond x = 1.5 holds about a sixth
// of the points.
SurfaceInput ellipsoid_cloud() {
  return test::sample_ellipsoid(Vec3(3.0, 1.0, 0.8), 6000, 7).cloud();
}

bool in_dense_end(const Vec3& p) { return p.x() > 1.5; }

// The share of spheres most of whose labelled points lie in the dense end.
double dense_share(const SurfaceInput& cloud, const Result& result) {
  const std::size_t spheres = result.medial_mesh.spheres.size();
  std::vector<int> dense(spheres, 0), all(spheres, 0);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const int label = result.labels[i];
    if (label < 0) continue;
    ++all[label];
    dense[label] += in_dense_end(cloud.points[i]);
  }
  int count = 0;
  for (std::size_t s = 0; s < spheres; ++s) count += 2 * dense[s] > all[s];
  return double(count) / double(spheres);
}

Options with_spheres(int count) {
  Options options;
  options.run.target.spheres = count;
  options.threads = 1;
  return options;
}

TEST(Density, AUniformFieldChangesNothing) {
  const SurfaceInput cloud = ellipsoid_cloud();
  const Result plain = skeletonize(cloud, with_spheres(30));
  for (double value : {1.0, 3.0}) {
    SurfaceInput uniform = cloud;
    uniform.density.assign(cloud.points.size(), value);
    const Result result = skeletonize(uniform, with_spheres(30));
    ASSERT_EQ(result.medial_mesh.spheres.size(), plain.medial_mesh.spheres.size());
    for (std::size_t s = 0; s < plain.medial_mesh.spheres.size(); ++s) {
      EXPECT_EQ(result.medial_mesh.spheres[s].center, plain.medial_mesh.spheres[s].center)
          << "density " << value;
      EXPECT_EQ(result.medial_mesh.spheres[s].radius, plain.medial_mesh.spheres[s].radius);
    }
    EXPECT_EQ(result.labels, plain.labels);
  }
}

TEST(Density, AFourToOneFieldMovesSpheresIntoTheDenseRegion) {
  const SurfaceInput cloud = ellipsoid_cloud();
  SurfaceInput weighted = cloud;
  for (const Vec3& p : cloud.points) weighted.density.push_back(in_dense_end(p) ? 4.0 : 1.0);
  const double uniform = dense_share(cloud, skeletonize(cloud, with_spheres(30)));
  const double dense = dense_share(weighted, skeletonize(weighted, with_spheres(30)));
  EXPECT_GT(uniform, 0.0);
  EXPECT_GE(dense, 2.0 * uniform) << "uniform " << uniform << ", 4:1 " << dense;
}

// The starts are ranked by their error with each distance weighed by (d / d_max)²: a 4 : 1 field
// counts the sparse end's distances a sixteenth; a uniform field weighs nothing.
TEST(Density, TheStartsAreRankedByTheErrorTheFieldWeighs) {
  const SurfaceInput cloud = ellipsoid_cloud();
  SurfaceInput weighted = cloud, uniform = cloud;
  for (const Vec3& p : cloud.points) weighted.density.push_back(in_dense_end(p) ? 4.0 : 1.0);
  uniform.density.assign(cloud.points.size(), 4.0);
  Options options = with_spheres(30);
  options.starts = 2;
  const Result result = skeletonize(weighted, options);
  ASSERT_EQ(result.start_errors.size(), 2u);
  EXPECT_TRUE(result.start_errors_weighted);
  // Neither skeleton is split (the ellipsoid's are one piece): the least weighted error is kept.
  const double kept = result.start_errors[result.start_kept];
  EXPECT_EQ(kept, *std::min_element(result.start_errors.begin(), result.start_errors.end()));
  EXPECT_LE(kept, result.measured_error);
  const Result plain = skeletonize(uniform, options);
  EXPECT_FALSE(plain.start_errors_weighted);
  EXPECT_EQ(plain.start_errors[plain.start_kept], plain.measured_error);
}

TEST(Density, AnErrorThresholdIsMetWhereTheDensitySays) {
  const SurfaceInput cloud = ellipsoid_cloud();
  SurfaceInput weighted = cloud;
  for (const Vec3& p : cloud.points) weighted.density.push_back(in_dense_end(p) ? 4.0 : 1.0);
  Options options;
  options.threads = 1;
  options.run.target.error = 0.01;
  const Result plain = skeletonize(cloud, options);
  const Result result = skeletonize(weighted, options);
  EXPECT_GT(dense_share(weighted, result) * result.medial_mesh.spheres.size(),
            dense_share(cloud, plain) * plain.medial_mesh.spheres.size());
}

TEST(Density, ThinningCarriesTheMeanOfThePointsACellStandsFor) {
  SurfaceInput cloud = ellipsoid_cloud();
  for (std::size_t i = 0; i < cloud.points.size(); ++i) cloud.density.push_back(i % 2 ? 3.0 : 1.0);
  PrepareOptions options;
  options.max_points = 1000;
  const PrepareReport report = prepare_surface(cloud, options);
  ASSERT_LT(cloud.points.size(), 1500u);
  ASSERT_EQ(cloud.density.size(), cloud.points.size());
  // Each prepared point: the mean of the input points it stands for.
  std::vector<double> sum(cloud.points.size(), 0.0), count(cloud.points.size(), 0.0);
  for (std::size_t i = 0; i < report.stand_in.size(); ++i)
    if (report.stand_in[i] >= 0) {
      sum[report.stand_in[i]] += i % 2 ? 3.0 : 1.0;
      count[report.stand_in[i]] += 1.0;
    }
  for (std::size_t v = 0; v < cloud.points.size(); ++v)
    EXPECT_NEAR(cloud.density[v], sum[v] / count[v], 1e-12) << v;
}

TEST(Density, BadFieldsAreRefusedWithTheirProblem) {
  const auto problem = [](std::vector<double> density, std::size_t points) {
    try {
      check_density(density, points);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(problem({1.0, -2.0, 1.0}, 3), "the density of point 1 is negative (-2)");
  EXPECT_EQ(problem({1.0, nan, 1.0}, 3), "the density of point 1 is not a number");
  EXPECT_EQ(problem({1.0, 1.0 / 0.0, 1.0}, 3), "the density of point 1 is infinite");
  EXPECT_EQ(problem({1.0, 1.0}, 3), "the density has 2 values for 3 points");
  EXPECT_EQ(problem({0.0, 0.0, 0.0}, 3),
            "every density value is 0: some point must have a positive density");
  EXPECT_EQ(problem({0.0, 2.0, 0.0}, 3), "");
  SurfaceInput cloud = ellipsoid_cloud();
  cloud.density.assign(10, 1.0);
  EXPECT_THROW(skeletonize(cloud, with_spheres(10)), InvalidInput);
  EXPECT_THROW(density_by_rule(cloud, "curvy"), InvalidOption);
  EXPECT_THROW(density_by_rule(cloud, "distance-to:1,2,3"), InvalidOption);
  EXPECT_THROW(density_by_rule(cloud, "distance-to:1,2,3,-1"), InvalidOption);
}

TEST(Density, RulesGiveTheirValues) {
  SurfaceInput cloud = ellipsoid_cloud();
  const std::vector<double> near = density_by_rule(cloud, "distance-to:3,0,0,1,6");
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    EXPECT_EQ(near[i], (cloud.points[i] - Vec3(3, 0, 0)).norm() <= 1.0 ? 6.0 : 1.0);
  // The ellipsoid curves most at its ends (x = ±3): they get the highest density.
  const std::vector<double> curved = density_by_rule(cloud, "curvature");
  double ends = 0.0, middle = 0.0;
  int ends_count = 0, middle_count = 0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    EXPECT_GE(curved[i], 1.0);
    EXPECT_LE(curved[i], 4.0);
    if (std::abs(cloud.points[i].x()) > 2.7) ends += curved[i], ++ends_count;
    if (std::abs(cloud.points[i].x()) < 0.5) middle += curved[i], ++middle_count;
  }
  EXPECT_GT(ends / ends_count, 1.5 * middle / middle_count);
}

using DensityCli = test::CliTest;

TEST_F(DensityCli, FieldsAndFilesAreReadAndTheirErrorsNameTheFile) {
  write("four.xyz", "0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n");
  SurfaceInput read = read_surface_as_stored(path("four.xyz"), "density");
  EXPECT_EQ(read.density, (std::vector<double>{1, 2, 3, 4}));
  write(
      "four.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty float weight\nend_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n");
  read = read_surface_as_stored(path("four.ply"), "weight");
  EXPECT_EQ(read.density, (std::vector<double>{1, 2, 3, 4}));
  try {
    read_surface_as_stored(path("four.ply"), "density");
    ADD_FAILURE() << "a missing property was read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("four.ply: no vertex property 'density'"),
              std::string::npos)
        << e.what();
  }

  write_surface(path("ball.xyz"), test::sample_sphere(Vec3::Zero(), 1.0, 400, 3).cloud(false));
  const auto skeletonize_ball = [&](const std::string& options) {
    return run("skeletonize " + path("ball.xyz") + " -n 5 -o " + path("out.ply") + " " + options);
  };
  std::string values;
  for (std::size_t i = 0; i < 400; ++i) values += i == 7 ? "-1\n" : "1\n";
  write("density.txt", values);
  auto r = skeletonize_ball("--density " + path("density.txt"));
  EXPECT_EQ(r.exit_code, 1);
  test::expect_one_line_error(r, "density.txt: the density of point 7 is negative (-1)");
  EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
  write("density.txt", "1\n1\n");
  r = skeletonize_ball("--density " + path("density.txt"));
  EXPECT_EQ(r.exit_code, 1);
  test::expect_one_line_error(r, "density.txt: 2 density values for the input's 400 points");
  r = skeletonize_ball("--density-field weight");
  EXPECT_EQ(r.exit_code, 1);
  test::expect_one_line_error(r, "ball.xyz: line 1: expected 4 or 7 columns");
  r = skeletonize_ball("--density distance-to:0,0");
  EXPECT_EQ(r.exit_code, 2);
  test::expect_one_line_error(r, "distance-to:X,Y,Z,R[,D]");
  r = skeletonize_ball("--density curvature --density-field weight");
  EXPECT_EQ(r.exit_code, 2);
  test::expect_one_line_error(r, "give one");
  r = skeletonize_ball("--density distance-to:1,0,0,0.5 -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(path("out.ply")));
}

}  // namespace
}  // namespace vmas

namespace vmas {
namespace {

TEST(Density, MergedDuplicatesCarryTheirMeanDensity) {
  SurfaceInput cloud;
  cloud.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0)};
  cloud.density = {1.0, 2.0, 4.0, 3.0, 7.0};
  clean_surface(cloud);
  ASSERT_EQ(cloud.points.size(), 3u);
  EXPECT_EQ(cloud.density, (std::vector<double>{4.0, 2.0, 3.0}));
  SurfaceInput uniform;
  uniform.points = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)};
  uniform.density.assign(4, 0.1);  // three 0.1 add up to more than 0.3
  clean_surface(uniform);
  EXPECT_EQ(uniform.density, (std::vector<double>{0.1, 0.1}));
}

}  // namespace
}  // namespace vmas
