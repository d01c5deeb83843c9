// Stray clusters: small groups of points apart from the object go; sparse parts of the object
// (a thin antenna, a tail), clean samplings and data made of many pieces stay whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "prepare/prepare.hpp"
#include "prepare/stray_clusters.hpp"
#include "test_shapes.hpp"

namespace vmas {
namespace {

// `count` points scattered about `center` with deviation `spread`.
std::vector<Vec3> clump(const Vec3& center, double spread, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, spread);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i)
    points.push_back(center + test::draw_xyz([&] { return gauss(rng); }));
  return points;
}

void append(std::vector<Vec3>& points, const std::vector<Vec3>& more) {
  points.insert(points.end(), more.begin(), more.end());
}

TEST(StrayClusters, ClumpsApartFromTheObjectGoAndNothingElse) {
  std::vector<Vec3> points = test::sample_sphere(Vec3::Zero(), 1.0, 10000, 1).points;
  const int body = static_cast<int>(points.size());
  append(points, clump(Vec3(1.6, 0.3, 0.2), 0.01, 25, 2));  // 0.6 off the sphere, 25 points
  append(points, clump(Vec3(-0.5, -1.4, 0.9), 0.03, 40, 3));
  points.emplace_back(0.0, 0.0, 1.5);  // a lone stray, half a radius above the pole
  const StrayClusterSplit split = without_stray_clusters(points);
  EXPECT_EQ(split.clusters, 3u);
  ASSERT_EQ(split.kept.size(), static_cast<std::size_t>(body));
  for (int i = 0; i < body; ++i) EXPECT_EQ(split.kept[i], i);
}

TEST(StrayClusters, AThinAntennaAndASparserTailStay) {
  std::vector<Vec3> points = test::sample_sphere(Vec3::Zero(), 1.0, 10000, 4).points;
  // The sphere's sampling: about 0.035 between neighbours. An antenna of 15 points at that
  // spacing leaving the pole, and a tail of 10 points five times sparser leaving the equator
  // (farther apart than the sphere's 16 nearest neighbours).
  for (int i = 1; i <= 15; ++i) points.emplace_back(0.0, 0.0, 1.0 + 0.035 * i);
  for (int i = 1; i <= 10; ++i) points.emplace_back(1.0 + 0.18 * i, 0.0, 0.0);
  const StrayClusterSplit split = without_stray_clusters(points);
  EXPECT_EQ(split.clusters, 0u);
  EXPECT_EQ(split.kept.size(), points.size());
  // The same antenna 0.6 above the pole (17 spacings, farther than its length) is a stray
  // cluster.
  for (int i = 0; i < 15; ++i) points[points.size() - 25 + i].z() += 0.6;
  EXPECT_EQ(without_stray_clusters(points).clusters, 1u);
}

// A single range scan sees a patch of surface behind an occlusion edge across a gap of a few
// spacings: the patch is larger than the gap, a part of the object.
TEST(StrayClusters, APatchSeenAcrossAGapStays) {
  std::vector<Vec3> points = test::sample_sphere(Vec3::Zero(), 1.0, 10000, 8).points;
  const std::size_t sphere = points.size();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> square(-0.2, 0.2);
  for (int i = 0; i < 60; ++i) points.emplace_back(1.25, square(rng), square(rng));
  EXPECT_EQ(without_stray_clusters(points).clusters, 0u);
  // The same patch far out is a stray cluster.
  for (std::size_t i = sphere; i < points.size(); ++i) points[i].x() += 1.0;
  EXPECT_EQ(without_stray_clusters(points).clusters, 1u);
}

TEST(StrayClusters, CleanSamplingsStayWhole) {
  for (int count : {2000, 5000, 30000}) {
    for (const auto& points : {test::sample_torus(1.0, 0.3, count, 7).points,
                               test::sample_box(Vec3(1.0, 0.6, 0.3), count, 8).points,
                               test::sample_ellipsoid(Vec3(1.0, 0.5, 0.02), count, 9).points}) {
      const StrayClusterSplit split = without_stray_clusters(points);
      EXPECT_EQ(split.kept.size(), points.size()) << count << " points";
    }
  }
}

// A part of several small pieces (beads on a string, far apart) is the data, not strays.
TEST(StrayClusters, DataInManyPiecesStaysWhole) {
  std::vector<Vec3> points;
  for (int bead = 0; bead < 150; ++bead)
    append(points, test::sample_sphere(Vec3(0.5 * bead, 0.0, 0.0), 0.1, 60, bead + 10).points);
  EXPECT_EQ(without_stray_clusters(points).kept.size(), points.size());
}

// What a point stands for counts: a clump thinned to a few points, that held 2 % of the input.
TEST(StrayClusters, APieceIsWeighedByTheInputPointsItStandsFor) {
  std::vector<Vec3> points = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 5).points;
  append(points, clump(Vec3(2.0, 0.0, 0.0), 0.01, 20, 6));
  std::vector<std::size_t> weights(points.size(), 1);
  EXPECT_EQ(without_stray_clusters(points, weights).clusters, 1u);
  std::fill(weights.end() - 20, weights.end(), 6);  // 120 of 5 120 input points: 2.3 %
  EXPECT_EQ(without_stray_clusters(points, weights).clusters, 0u);
}

// Preparation removes them on a clean cloud and with --denoise off, reports the input points,
// and keeps them when told to.
TEST(StrayClusters, PreparationRemovesAndReportsThem) {
  std::vector<Vec3> points = test::sample_sphere(Vec3::Zero(), 1.0, 8000, 11).points;
  const std::size_t body = points.size();
  append(points, clump(Vec3(0.0, 1.7, 0.0), 0.02, 30, 12));
  for (auto denoise : {PrepareOptions::Denoise::Auto, PrepareOptions::Denoise::Off}) {
    SurfaceInput cloud;
    cloud.points = points;
    PrepareOptions options;
    options.denoise = denoise;
    const PrepareReport report = prepare_surface(cloud, options);
    EXPECT_EQ(report.stray_clusters, 1u);
    ASSERT_EQ(report.stray_points.size(), 30u);
    EXPECT_EQ(report.stray_points.front(), static_cast<int>(body));
    EXPECT_LE(cloud.points.size(), body);
    options.remove_stray_clusters = false;
    SurfaceInput kept;
    kept.points = points;
    EXPECT_EQ(prepare_surface(kept, options).stray_clusters, 0u);
  }
}

}  // namespace
}  // namespace vmas
