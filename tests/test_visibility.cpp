#include <gtest/gtest.h>
#include <omp.h>

#include <vector>

#include "test_shapes.hpp"
#include "prepare/visibility.hpp"

namespace vmas {
namespace {

TEST(VisibilityVotes, OutwardNormalsFaceTheirViewersAndHiddenPointsGetNone) {
  test::Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 4000, 41);
  // A small ball inside: no view sees it.
  const test::Sample inner = test::sample_sphere(Vec3::Zero(), 0.3, 200, 42);
  std::vector<Vec3> points = s.points, normals = s.normals;
  points.insert(points.end(), inner.points.begin(), inner.points.end());
  normals.insert(normals.end(), inner.normals.begin(), inner.normals.end());
  normals[0] = -normals[0];
  const std::vector<double> votes = visibility_votes(points, normals, 0.2);
  ASSERT_EQ(votes.size(), points.size());
  EXPECT_LT(votes[0], -0.3);
  for (std::size_t i = 1; i < s.points.size(); ++i) ASSERT_GT(votes[i], 0.3) << i;
  for (std::size_t i = s.points.size(); i < points.size(); ++i) EXPECT_EQ(votes[i], 0.0) << i;
}

TEST(VisibilityVotes, BothSidesOfAThinPlateFaceOutward) {
  // Sides 0.05 apart, pixels of 0.02: each side is seen from its own half of the views only.
  const test::Sample s = test::sample_box(Vec3(2.0, 1.0, 0.05), 8000, 43);
  const std::vector<double> votes = visibility_votes(s.points, s.normals, 0.02);
  int facing = 0;
  for (double v : votes) facing += v > 0.0;
  EXPECT_GT(facing, 0.99 * s.points.size());
}

TEST(VisibilityVotes, SameVotesForAnyThreadCountAndNoneForNoPoints) {
  const test::Sample s = test::sample_torus(1.0, 0.3, 3000, 44);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<double> one = visibility_votes(s.points, s.normals, 0.05);
  omp_set_num_threads(2);
  const std::vector<double> two = visibility_votes(s.points, s.normals, 0.05);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
  EXPECT_TRUE(visibility_votes({}, {}, 0.1).empty());
  // A pixel of 0 (duplicates, a spacing of 0) is raised, not divided by.
  const std::vector<Vec3> same(50, Vec3(1.0, 2.0, 3.0)), up(50, Vec3::UnitZ());
  const std::vector<double> votes = visibility_votes(same, up, 0.0);
  for (double v : votes) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace vmas
