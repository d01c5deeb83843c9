#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <flann/flann.hpp>
#include <limits>
#include <random>

#include "core/flann_query.hpp"
#include "core/kdtree.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace {

std::vector<Vec3> random_points(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Vec3> points(count);
  for (auto& p : points) p = test::draw_xyz([&] { return uniform(rng); });
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

// FLANN's single-tree search for one neighbour, as KdTree::nearest used it before having its own.
class FlannNearest : public flann::ResultSet<double> {
 public:
  bool full() const override { return true; }
  void addPoint(double distance, size_t index) override {
    if (distance < distance_ || (distance == distance_ && index < index_)) {
      distance_ = distance;
      index_ = index;
    }
  }
  double worstDist() const override { return distance_; }
  double distance_ = std::numeric_limits<double>::max();
  size_t index_ = 0;
};

TEST(KdTree, NearestMatchesFlannDownToTies) {
  // A shuffled grid queried at grid points, edge midpoints and cell centres: many exact ties,
  // which FLANN resolves by its traversal order.
  std::vector<Vec3> points;
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 9; ++y)
      for (int z = 0; z < 7; ++z) points.emplace_back(0.5 * x, 0.25 * y, z);
  std::shuffle(points.begin(), points.end(), std::mt19937(4));
  const KdTree tree(points);
  std::vector<double> coordinates;
  for (const Vec3& p : points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  flann::KDTreeSingleIndex<flann::L2_Simple<double>> index(
      flann::Matrix<double>(coordinates.data(), points.size(), 3),
      flann::KDTreeSingleIndexParams(10));
  index.buildIndex();
  std::vector<Vec3> queries = random_points(300, 5);
  for (int x = -1; x < 25; ++x)
    for (int y = -1; y < 19; ++y)
      for (int z = -1; z < 15; z += 3) queries.emplace_back(0.25 * x, 0.125 * y, 0.5 * z);
  for (const Vec3& query : queries) {
    FlannNearest expected;
    index.findNeighbors(expected, query.data(), flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED));
    double squared_distance = -1.0;
    EXPECT_EQ(tree.nearest(query, &squared_distance), static_cast<int>(expected.index_));
    EXPECT_EQ(squared_distance, expected.distance_);
  }
}

TEST(KdTree, NearestWithinABoundIsTheNearestDownToTiesOrNone) {
  // The grid's ties again, with bounds just past, at and below each nearest distance (the
  // shrinking ball searches only inside its ball).
  std::vector<Vec3> points;
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 9; ++y)
      for (int z = 0; z < 7; ++z) points.emplace_back(0.5 * x, 0.25 * y, z);
  std::shuffle(points.begin(), points.end(), std::mt19937(4));
  const KdTree tree(points);
  std::vector<Vec3> queries = random_points(300, 5);
  for (int x = -1; x < 25; ++x)
    for (int y = -1; y < 19; ++y)
      for (int z = -1; z < 15; z += 3) queries.emplace_back(0.25 * x, 0.125 * y, 0.5 * z);
  int ties_found = 0;
  for (const Vec3& query : queries) {
    double nearest_squared = 0.0;
    const int nearest = tree.nearest(query, &nearest_squared);
    int equally_near = 0;
    for (const Vec3& p : points) equally_near += (p - query).squaredNorm() == nearest_squared;
    ties_found += equally_near > 1;
    for (const double bound : {std::nextafter(nearest_squared, 1e300), 4.0 * nearest_squared + 1.0}) {
      double squared = -1.0;
      EXPECT_EQ(tree.nearest_within(query, bound, &squared), nearest);
      EXPECT_EQ(squared, nearest_squared);
    }
    EXPECT_EQ(tree.nearest_within(query, nearest_squared), -1);  // nothing strictly nearer
  }
  EXPECT_GT(ties_found, 100);
}

TEST(FlannQuery, SortedRadiusResultsMatchFlannDownToTies) {
  // Grid points at equal distances from grid queries: the order among equals is FLANN's (lower
  // index first), which PCL's MLS sums in.
  std::vector<float> coordinates;
  std::vector<Vec3> grid;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 6; ++z) grid.emplace_back(x, y, z);
  std::shuffle(grid.begin(), grid.end(), std::mt19937(7));
  for (const Vec3& p : grid)
    coordinates.insert(coordinates.end(), {float(p.x()), float(p.y()), float(p.z())});
  flann::KDTreeSingleIndex<flann::L2_Simple<float>> index(
      flann::Matrix<float>(coordinates.data(), grid.size(), 3), flann::KDTreeSingleIndexParams(15));
  index.buildIndex();
  const flann::SearchParams sorted(-1, 0.0f, true);
  std::size_t compared = 0;
  for (int q = 0; q < 60; ++q) {
    const float query[3] = {float(q % 10), float(q % 8) + 0.5f * (q % 2), float(q % 6)};
    for (const float squared_radius : {2.0f, 5.0f, 12.5f}) {
      std::vector<std::vector<std::size_t>> expected_indices;
      std::vector<std::vector<float>> expected_squared;
      index.radiusSearch(flann::Matrix<float>(const_cast<float*>(query), 1, 3), expected_indices,
                         expected_squared, squared_radius, sorted);
      std::vector<std::size_t> found;
      std::vector<float> squared;
      const std::size_t count =
          flann_query::within_radius(index, query, squared_radius, 0, found, squared, sorted);
      EXPECT_EQ(count, expected_indices[0].size());
      EXPECT_EQ(found, expected_indices[0]);
      EXPECT_EQ(squared, expected_squared[0]);
      compared += found.size();
    }
  }
  EXPECT_GT(compared, 1000u);
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
