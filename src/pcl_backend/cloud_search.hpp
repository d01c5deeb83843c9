#pragma once
// Neighbour searches as PCL makes them (its statistical outlier rule and MLS are defined on
// them): over a float copy of the points moved by -centroid, in FLANN's single KD-tree of 15
// points per leaf, the tree pcl::KdTreeFLANN builds, so the same neighbours in the same order.
// Thread-safe queries.
#include <memory>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class FloatCloudSearch {
 public:
  // `sorted`: whether within() sorts its answers nearest first (nearest() always does).
  FloatCloudSearch(const std::vector<Vec3>& points, const Vec3& centroid, bool sorted);
  ~FloatCloudSearch();
  FloatCloudSearch(const FloatCloudSearch&) = delete;
  FloatCloudSearch& operator=(const FloatCloudSearch&) = delete;

  // The min(k, point count) points nearest to `query` (moved and rounded as the points were), sorted;
  // returns their count.
  int nearest(const Vec3& query, int k, std::vector<int>& indices,
              std::vector<float>& squared_distances) const;
  // The points within `radius` of `query`; returns their count.
  int within(const Vec3& query, double radius, std::vector<int>& indices,
             std::vector<float>& squared_distances) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace internal
}  // namespace vmas
