#include "pcl_backend/cloud_search.hpp"

#include <type_traits>

#include "pcl_backend/flann_search.hpp"
// PCL's template sources, so that the classes used here are compiled into vmas: of PCL's
// libraries only libpcl_common is linked (the search and kdtree libraries would slow every start
// of vmas with their relocations).
#include <pcl/impl/pcl_base.hpp>
#include <pcl/search/impl/search.hpp>

namespace vmas::internal {

static_assert(std::is_same_v<pcl::Indices, std::vector<int>>,
              "vmas passes its index vectors to PCL as they are");

struct FloatCloudSearch::Impl {
  Vec3 centroid;
  FlannSearch search;
  Impl(const std::vector<Vec3>& points, const Vec3& centroid, bool sorted)
      : centroid(centroid), search(sorted) {
    search.setInputCloud(float_cloud(points, centroid));
  }
};

FloatCloudSearch::FloatCloudSearch(const std::vector<Vec3>& points, const Vec3& centroid,
                                   bool sorted)
    : impl_(std::make_unique<Impl>(points, centroid, sorted)) {}

FloatCloudSearch::~FloatCloudSearch() = default;

int FloatCloudSearch::nearest(const Vec3& query, int k, std::vector<int>& indices,
                              std::vector<float>& squared_distances) const {
  return impl_->search.nearestKSearch(float_point(query, impl_->centroid), k, indices,
                                      squared_distances);
}

int FloatCloudSearch::within(const Vec3& query, double radius, std::vector<int>& indices,
                             std::vector<float>& squared_distances) const {
  return impl_->search.radiusSearch(float_point(query, impl_->centroid), radius, indices,
                                    squared_distances);
}

}  // namespace vmas::internal
