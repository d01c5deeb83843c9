#pragma once
// The weighted mean of densities (SurfaceInput::density) over a cluster or a cell: exactly the
// common value when they are all equal, so that a uniform density weighs every cluster alike to
// the bit and leaves the output as it is without one (docs/design.md, "Density").
#include <algorithm>
#include <limits>

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
    // 0 when nothing was added.
    double value() const {
      if (low_ == high_) return low_;
      if (low_ > high_) return 0.0;
      return weight_ > 0.0 ? sum_ / weight_ : 0.5 * (low_ + high_);
    }

   private:
    double sum_ = 0.0, weight_ = 0.0;
    double low_ = std::numeric_limits<double>::infinity();
    double high_ = -std::numeric_limits<double>::infinity();
  };

}  // namespace )
}  // namespace vmas
