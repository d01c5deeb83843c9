#pragma once
// PCL's MovingLeastSquares surfaces of a cloud with support `radius`, fitted on a voxel grid's
// centroids (a bounded number of samples per fit whatever the density, and the voxel averages are
// already less noisy). A point goes onto the surface fitted at its nearest centroid.
#include <memory>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class MlsSurfaces {
 public:
  // Fits at every centroid, or only at those nearest to points[i] for i in `only` when given:
  // each fit depends on its neighbourhood alone, so those are the fits of the whole surface.
  // Uses every OpenMP thread.
  MlsSurfaces(const std::vector<Vec3>& points, double radius, const std::vector<int>* only);
  ~MlsSurfaces();
  MlsSurfaces(const MlsSurfaces&) = delete;
  MlsSurfaces& operator=(const MlsSurfaces&) = delete;

  // `point` moved onto its surface, and the surface normal there; false when no valid fit.
  // Thread-safe.
  bool project(const Vec3& point, Vec3& projected, Vec3& normal) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace internal
}  // namespace vmas
