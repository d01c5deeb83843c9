#include "pcl_backend/mls.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include <pcl/filters/voxel_grid.h>
#include <pcl/surface/mls.h>
// PCL's template sources, so that the classes used here are compiled into vmas: of PCL's
// libraries only libpcl_common is linked (libpcl_surface pulls VTK in, and the filters, search
// and kdtree libraries would slow every start of vmas with their relocations).
#include <pcl/filters/impl/voxel_grid.hpp>
#include <pcl/impl/pcl_base.hpp>
#include <pcl/kdtree/impl/kdtree_flann.hpp>
#include <pcl/search/impl/kdtree.hpp>
#include <pcl/search/impl/organized.hpp>
#include <pcl/search/impl/search.hpp>
#include <pcl/surface/impl/mls.hpp>

#include "core/kdtree.hpp"
#include "core/principal_axes.hpp"
#include "pcl_backend/flann_search.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vmas::internal {

struct MlsSurfaces::Impl {
  Vec3 centroid;
  std::optional<KdTree> tree;  // over the fitting centroids (centred)
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointNormal> mls;  // holds the fits
};

MlsSurfaces::MlsSurfaces(const std::vector<Vec3>& points, double radius,
                         const std::vector<int>* only)
    : impl_(std::make_unique<Impl>()) {
  if (!(radius > 0.0)) throw std::logic_error("MlsSurfaces: the radius must be positive");
  constexpr double kFitsPerRadius = 6.0;        // voxel size of the fitting cloud: radius / this
  constexpr double kMaxVoxelsPerAxis = 1000.0;  // keeps VoxelGrid's integer keys from overflowing
  impl_->centroid = centroid_of(points);
  const auto cloud = float_cloud(points, impl_->centroid);
  const Box box = bounding_box(points);
  const float voxel = static_cast<float>(
      std::max(radius / kFitsPerRadius, box.sizes().maxCoeff() / kMaxVoxelsPerAxis));
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(cloud);
  grid.setLeafSize(voxel, voxel, voxel);
  auto fitting = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  grid.filter(*fitting);
  std::vector<Vec3> fitting_points(fitting->size());
  for (std::size_t i = 0; i < fitting->size(); ++i)
    fitting_points[i] = (*fitting)[i].getVector3fMap().cast<double>();
  impl_->tree.emplace(fitting_points);

  auto& mls = impl_->mls;
  mls.setInputCloud(fitting);
  if (only) {
    auto nearest = std::make_shared<pcl::Indices>();
    for (int i : *only) nearest->push_back(impl_->tree->nearest(points[i] - impl_->centroid));
    std::sort(nearest->begin(), nearest->end());
    nearest->erase(std::unique(nearest->begin(), nearest->end()), nearest->end());
    mls.setIndices(nearest);
  }
  mls.setSearchMethod(std::make_shared<FlannSearch>(true));
  mls.setSearchRadius(radius);
  mls.setPolynomialOrder(2);
  mls.setCacheMLSResults(true);
#ifdef _OPENMP
  mls.setNumberOfThreads(static_cast<unsigned>(omp_get_max_threads()));
#endif
  pcl::PointCloud<pcl::PointNormal> fitted;
  mls.process(fitted);
}

MlsSurfaces::~MlsSurfaces() = default;

bool MlsSurfaces::project(const Vec3& point, Vec3& projected, Vec3& normal) const {
  constexpr int kPolynomialCoefficients = 6;  // order 2
  const Vec3 local = point - impl_->centroid;
  const pcl::MLSResult& fit = impl_->mls.getMLSResults()[impl_->tree->nearest(local)];
  if (!fit.valid) return false;
  const pcl::MLSResult::MLSProjectionResults on =
      fit.projectPoint(local, pcl::MLSResult::SIMPLE, kPolynomialCoefficients);
  if (!on.point.allFinite() || !on.normal.allFinite()) return false;
  projected = on.point + impl_->centroid;
  normal = on.normal;
  return true;
}

}  // namespace vmas::internal
