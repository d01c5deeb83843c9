// Tests of the subsample stage (src/core/subsample.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/subsample.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace {

TEST(Subsample, KeepsAboutTheBudgetOnePointPerCellAndMapsEveryPointToANearbyOne) {
  const test::Sample box = test::sample_box(Vec3(1.0, 2.0, 0.5), 60000, 3);
  const Subsample thin = subsample(box.points, 5000);
  EXPECT_GE(thin.kept.size(), 4000u);
  EXPECT_LE(thin.kept.size(), 5000u);
  ASSERT_EQ(thin.representative.size(), box.points.size());
  EXPECT_TRUE(std::is_sorted(thin.kept.begin(), thin.kept.end()));
  const double cell_diagonal = std::sqrt(3.0) * thin.leaf;
  std::vector<int> represented(thin.kept.size(), 0);
  for (std::size_t i = 0; i < box.points.size(); ++i) {
    const int r = thin.representative[i];
    ASSERT_GE(r, 0);
    ASSERT_LT(r, static_cast<int>(thin.kept.size()));
    ++represented[r];
    EXPECT_LE((box.points[i] - box.points[thin.kept[r]]).norm(), cell_diagonal) << i;
  }
  // A kept point stands for itself, and no two kept points share a cell.
  for (std::size_t j = 0; j < thin.kept.size(); ++j)
    EXPECT_EQ(thin.representative[thin.kept[j]], j);
  std::set<std::array<long, 3>> cells;
  const Vec3 origin = bounding_box(box.points).min();
  for (int k : thin.kept) {
    const Vec3 c = ((box.points[k] - origin) / thin.leaf).array().floor();
    cells.insert({long(c.x()), long(c.y()), long(c.z())});
  }
  EXPECT_EQ(cells.size(), thin.kept.size());
  // The same input gives the same subsample.
  const Subsample again = subsample(box.points, 5000);
  EXPECT_EQ(again.kept, thin.kept);
  EXPECT_EQ(again.representative, thin.representative);
}

TEST(Subsample, SmallCloudsAndAZeroBudgetKeepEveryPoint) {
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 3000, 5);
  for (std::size_t budget : {std::size_t(0), std::size_t(3000), std::size_t(10000)}) {
    const Subsample all = subsample(sphere.points, budget);
    ASSERT_EQ(all.kept.size(), 3000u) << budget;
    EXPECT_EQ(all.leaf, 0.0);
    for (int i = 0; i < 3000; ++i) EXPECT_EQ(all.representative[i], i);
  }
  // Every point at one place, or on a line: still one point per cell, no division by zero.
  const std::vector<Vec3> same(5000, Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(subsample(same, 1000).kept.size(), 1u);
  std::vector<Vec3> line;
  for (int i = 0; i < 5000; ++i) line.push_back(Vec3(i * 1e-3, 0.0, 0.0));
  const Subsample on_line = subsample(line, 1000);
  EXPECT_GE(on_line.kept.size(), 800u);
  EXPECT_LE(on_line.kept.size(), 1000u);
}

TEST(Subsample, PointsOfDifferentGroupsNeverShareACellsPoint) {
  const test::Sample box = test::sample_box(Vec3(1.0, 1.0, 1.0), 20000, 7);
  std::vector<std::uint8_t> groups(box.points.size());
  for (std::size_t i = 0; i < groups.size(); ++i) groups[i] = static_cast<std::uint8_t>(i % 3);
  const Subsample thin = subsample(box.points, 3000, groups);
  EXPECT_GE(thin.kept.size(), 2400u);
  EXPECT_LE(thin.kept.size(), 3000u);
  for (std::size_t i = 0; i < box.points.size(); ++i)
    EXPECT_EQ(groups[thin.kept[thin.representative[i]]], groups[i]) << i;
  EXPECT_THROW(subsample(box.points, 3000, std::vector<std::uint8_t>(5, 0)), InvalidArgument);
}

}  // namespace
}  // namespace vmas
