#pragma once
// The least-squares planes of neighbourhoods as PCL's computePointNormal fits them (in float,
// about the cloud's centroid, so that large coordinates keep their precision).
#include <memory>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class PlaneFits {
 public:
  explicit PlaneFits(const std::vector<Vec3>& points);
  ~PlaneFits();
  PlaneFits(const PlaneFits&) = delete;
  PlaneFits& operator=(const PlaneFits&) = delete;

  // The unit normal of the plane through the points of `indices` (NaN when they are fewer than
  // three or degenerate), and their surface variation (the least eigenvalue's share). Thread-safe.
  Vec3 normal(const std::vector<int>& indices, float& variation) const;

 private:
  struct Cloud;
  std::unique_ptr<Cloud> cloud_;
};

}  // namespace internal
}  // namespace vmas
