#include "pcl_backend/plane_fits.hpp"

#include <pcl/features/normal_3d.h>

#include "core/principal_axes.hpp"
#include "pcl_backend/flann_search.hpp"

namespace vmas::internal {

struct PlaneFits::Cloud {
  pcl::PointCloud<pcl::PointXYZ>::Ptr points;
};

PlaneFits::PlaneFits(const std::vector<Vec3>& points) : cloud_(std::make_unique<Cloud>()) {
  cloud_->points = float_cloud(points, centroid_of(points));
}

PlaneFits::~PlaneFits() = default;

Vec3 PlaneFits::normal(const std::vector<int>& indices, float& variation) const {
  Eigen::Vector4f plane;
  pcl::computePointNormal(*cloud_->points, indices, plane, variation);
  return plane.head<3>().cast<double>();
}

}  // namespace vmas::internal
