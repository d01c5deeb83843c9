#include <gtest/gtest.h>

#include <random>

#include "vmas/error.hpp"
#include "vmas/kdtree.hpp"

namespace vmas {
namespace {

std::vector<Vec3> random_points(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Vec3> points(count);
  for (auto& p : points) p = Vec3(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

TEST(KdTree, NearestMatchesBruteForce) {
  const auto points = random_points(2000, 1);
  const KdTree tree(points);
  for (const Vec3& query : random_points(200, 2)) {
    int best = 0;
    for (int i = 1; i < static_cast<int>(points.size()); ++i)
      if ((points[i] - query).squaredNorm() < (points[best] - query).squaredNorm()) best = i;
    double squared_distance = -1.0;
    EXPECT_EQ(tree.nearest(query, &squared_distance), best);
    EXPECT_NEAR(squared_distance, (points[best] - query).squaredNorm(), 1e-12);
  }
}

TEST(KdTree, KNearestIsSortedAndClampedToSize) {
  const auto points = random_points(5, 3);
  const KdTree tree(points);
  std::vector<int> indices;
  std::vector<double> distances;
  tree.k_nearest(Vec3::Zero(), 10, indices, distances);
  ASSERT_EQ(indices.size(), 5u);
  for (std::size_t i = 1; i < distances.size(); ++i) EXPECT_LE(distances[i - 1], distances[i]);
}

TEST(KdTree, EmptySetIsRejected) { EXPECT_THROW(KdTree(std::vector<Vec3>{}), InvalidInput); }

}  // namespace
}  // namespace vmas
