#pragma once
// Exact nearest-neighbour queries over a fixed point set (FLANN single KD-tree, unlimited
// checks). Queries are const and safe to run from several threads at once; the tree a kind of
// query needs is built by the first such query.
#include <memory>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

class KdTree {
 public:
  explicit KdTree(const std::vector<Vec3>& points);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  std::size_t size() const { return count_; }

  // Index of the point closest to `query`; its squared distance in `squared_distance`.
  int nearest(const Vec3& query, double* squared_distance = nullptr) const;
  // nearest() when it lies closer than √squared_bound (the same point, found sooner), else -1.
  int nearest_within(const Vec3& query, double squared_bound,
                     double* squared_distance = nullptr) const;

  // The k nearest points, closest first (fewer if the set is smaller than k).
  void k_nearest(const Vec3& query, int k, std::vector<int>& indices,
                 std::vector<double>& squared_distances) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t count_ = 0;
};

// The median distance from every `stride`-th of the tree's `points` to its nearest other point
// (a sampling's spacing); 0 for fewer than two points.
double median_spacing(const KdTree& tree, const std::vector<Vec3>& points, int stride = 1);

}  // namespace vmas
