#pragma once
// The weighted mean of densities (SurfaceInput::density) over a cluster or a cell: exactly the
// common value when they are all equal, so that a uniform density weighs every cluster alike to
// the bit and leaves the output as it is without one (docs/design.md, "Density").
#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class DensityMean {
 public:
  void add(double density, double weight) {
    sum_ += density * weight;
    weight_ += weight;
    low_ = std::min(low_, density);
    high_ = std::max(high_, density);
  }
  bool empty() const { return low_ > high_; }
  // 0 when nothing was added.
  double value() const {
    if (low_ == high_) return low_;
    if (empty()) return 0.0;
    return weight_ > 0.0 ? sum_ / weight_ : 0.5 * (low_ + high_);
  }

 private:
  double sum_ = 0.0, weight_ = 0.0;
  double low_ = std::numeric_limits<double>::infinity();
  double high_ = -std::numeric_limits<double>::infinity();
};

// The mean density of each of `groups` groups, point p in group `group_of[p]` (negative: in
// none); `none` for a group no point is in. Where points merge into one: duplicates, a voxel's
// points, the input rows a prepared vertex stands for.
template <typename Group>
std::vector<double> mean_density_by_group(const std::vector<double>& density,
                                          const std::vector<Group>& group_of, std::size_t groups,
                                          double none) {
  std::vector<DensityMean> means(groups);
  for (std::size_t p = 0; p < density.size(); ++p)
    if (group_of[p] >= 0) means[group_of[p]].add(density[p], 1.0);
  std::vector<double> values;
  values.reserve(groups);
  for (const DensityMean& mean : means) values.push_back(mean.empty() ? none : mean.value());
  return values;
}

}  // namespace internal
}  // namespace vmas
