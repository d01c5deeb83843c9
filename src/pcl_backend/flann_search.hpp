#pragma once
// pcl::search::KdTree's answers without FLANN's region per query (core/flann_query.hpp): the same
// FLANN tree as pcl::KdTreeFLANN builds (single KD-tree, 15 points per leaf, float coordinates),
// so the same neighbours. Dense clouds only (vmas's never hold NaN points); no indices. For the
// PCL stage's own sources: PCL's classes take it as their searcher.
#include <algorithm>
#include <memory>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/search.h>

#include "core/flann_query.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class FlannSearch : public pcl::search::Search<pcl::PointXYZ> {
 public:
  using Index = ::flann::KDTreeSingleIndex<::flann::L2_Simple<float>>;
  explicit FlannSearch(bool sorted) : pcl::search::Search<pcl::PointXYZ>("FlannSearch", sorted) {}

  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    if (indices) throw InvalidArgument("FlannSearch: indices are not supported");
    input_ = cloud;
    coordinates_.resize(3 * cloud->size());
    for (std::size_t i = 0; i < cloud->size(); ++i)
      std::copy_n((*cloud)[i].data, 3, coordinates_.begin() + 3 * i);
    index_ = std::make_unique<Index>(::flann::Matrix<float>(coordinates_.data(), cloud->size(), 3),
                                     ::flann::KDTreeSingleIndexParams(15));
    index_->buildIndex();
  }

  // As pcl::KdTreeFLANN::nearestKSearch (results always sorted).
  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& indices,
                     std::vector<float>& squared_distances) const override {
    const std::size_t wanted = std::min<std::size_t>(k, input_->size());
    indices.resize(wanted);
    squared_distances.resize(wanted);
    std::vector<std::size_t> found(wanted);
    if (wanted > 0)
      flann_query::k_nearest(*index_, point.data, wanted, found.data(), squared_distances.data(),
                             ::flann::SearchParams(-1, 0.0f));
    std::copy(found.begin(), found.end(), indices.begin());
    return static_cast<int>(wanted);
  }

  // As pcl::KdTreeFLANN::radiusSearch (sorted as the constructor says).
  int radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& indices,
                   std::vector<float>& squared_distances, unsigned int max_nn = 0) const override {
    std::vector<std::size_t> found;
    const std::size_t count =
        flann_query::within_radius(*index_, point.data, static_cast<float>(radius * radius),
                                   max_nn >= input_->size() ? 0 : max_nn, found, squared_distances,
                                   ::flann::SearchParams(-1, 0.0f, sorted_results_));
    indices.assign(found.begin(), found.end());
    return static_cast<int>(count);
  }

 private:
  std::vector<float> coordinates_;  // FLANN keeps a view into this buffer
  std::unique_ptr<Index> index_;
};

// Points moved by -centroid, in float: PCL computes in float, and large coordinates (far from
// the origin) would lose their precision otherwise.
inline pcl::PointXYZ float_point(const Vec3& point, const Vec3& centroid) {
  const Eigen::Vector3f p = (point - centroid).cast<float>();
  return pcl::PointXYZ(p.x(), p.y(), p.z());
}

inline pcl::PointCloud<pcl::PointXYZ>::Ptr float_cloud(const std::vector<Vec3>& points,
                                                       const Vec3& centroid) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) (*cloud)[i] = float_point(points[i], centroid);
  return cloud;
}

}  // namespace internal
}  // namespace vmas
