// Tests of the split stage (src/optimise/split.cpp).
#include <gtest/gtest.h>

#include "optimise/split.hpp"
#include "test_shapes.hpp"

namespace vmas {
namespace {

TEST(Split, ChoosesWorstEligibleNonAdjacentClusters) {
  const std::vector<double> errors = {5, 9, 8, 1, 7};
  // 1–2 adjacent, 2–4 adjacent.
  const std::vector<std::vector<int>> adjacency = {{}, {2}, {1, 4}, {}, {2}};
  const std::vector<bool> eligible(5, true);
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, eligible, 10),
            (std::vector<int>{1, 4, 0, 3}));
  // Eligible: above an error target of 4.
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, {true, true, true, false, true}, 10),
            (std::vector<int>{1, 4, 0}));
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, eligible, 2), (std::vector<int>{1, 4}));
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, {true, false, true, true, true}, 10),
            (std::vector<int>{2, 0, 3}));
}

}  // namespace
}  // namespace vmas
