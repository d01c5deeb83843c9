#pragma once
// vmas with PCL types, header-only: for programs that already use PCL (vmas itself does not
// expose PCL). Link vmas::vmas and PCL's common component.
//
//   pcl::PointCloud<pcl::PointXYZRGB> cloud;         // any point type with x, y, z
//   pcl::io::loadPCDFile("scan.pcd", cloud);          // organised clouds with NaNs are fine
//   vmas::Options options;
//   options.run.target.spheres = 40;
//   const vmas::Result result = vmas::skeletonize(cloud, options);
//   // result.labels[i]: the sphere of cloud[i] (-1 for NaN points, duplicates, outliers)
//   const std::vector<pcl::PointIndices> clusters = vmas::clusters_of(result);
//   const vmas::PclMedialMesh display = vmas::to_pcl(result.medial_mesh);
#include <pcl/PointIndices.h>
#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/types.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "vmas/vmas.hpp"

namespace vmas {

// The i-th point taken: cloud[i], or cloud[indices[i]]; an index past the cloud throws
// std::out_of_range.
template <typename PointT>
const PointT& point_taken(const pcl::PointCloud<PointT>& cloud, const pcl::Indices* indices,
                          std::size_t i) {
  return cloud.points.at(indices ? static_cast<std::size_t>((*indices)[i]) : i);
}

// The points of `cloud` in order (or those at `indices`, in their order), NaN ones included (an
// organised cloud's "no return"). Any PCL point type with x, y and z; a type with normal_x,
// normal_y and normal_z (pcl::PointNormal, PointXYZRGBNormal, PointXYZINormal, ...) gives its
// normals too, and a point whose normal is NaN or zero keeps its place and has one estimated.
// Other fields (colour, intensity, label) are not used.
template <typename PointT>
SurfaceInput to_surface(const pcl::PointCloud<PointT>& cloud,
                        const pcl::Indices* indices = nullptr) {
  static_assert(pcl::traits::has_xyz_v<PointT>, "vmas takes PCL point types with x, y and z");
  SurfaceInput surface;
  const std::size_t count = indices ? indices->size() : cloud.size();
  surface.points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const PointT& p = point_taken(cloud, indices, i);
    surface.points.emplace_back(p.x, p.y, p.z);
    if constexpr (pcl::traits::has_normal_v<PointT>)
      surface.normals.emplace_back(p.normal_x, p.normal_y, p.normal_z);
  }
  return surface;
}

// vmas::skeletonize of a PCL cloud; result.labels has one entry per point of `cloud`.
template <typename PointT>
Result skeletonize(const pcl::PointCloud<PointT>& cloud, const Options& options = {},
                   const ProgressCallback& progress = {}) {
  return skeletonize(to_surface(cloud), options, progress);
}

// Of the points at `indices` (pcl::Indices, as PCL's filters and segmentations give them);
// result.labels has one entry per index, in their order.
template <typename PointT>
Result skeletonize(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                   const Options& options = {}, const ProgressCallback& progress = {}) {
  return skeletonize(to_surface(cloud, &indices), options, progress);
}

// The same through PCL's shared pointers: `Cloud` is pcl::PointCloud<T> (PointCloud<T>::Ptr)
// or const pcl::PointCloud<T> (::ConstPtr).
template <typename Cloud>
Result skeletonize(const std::shared_ptr<Cloud>& cloud, const Options& options = {},
                   const ProgressCallback& progress = {}) {
  return skeletonize(*cloud, options, progress);
}
template <typename Cloud>
Result skeletonize(const std::shared_ptr<Cloud>& cloud, const pcl::Indices& indices,
                   const Options& options = {}, const ProgressCallback& progress = {}) {
  return skeletonize(*cloud, indices, options, progress);
}

// The clusters of result.labels as PCL segmentations give them: one pcl::PointIndices per
// sphere, holding the indices of its points in the cloud (with `indices`: the entries of
// `indices` whose labels these are). Dropped points are in none.
inline std::vector<pcl::PointIndices> clusters_of(const Result& result,
                                                  const pcl::Indices* indices = nullptr) {
  std::vector<pcl::PointIndices> clusters(result.medial_mesh.spheres.size());
  for (std::size_t i = 0; i < result.labels.size(); ++i)
    if (result.labels[i] >= 0)
      clusters[static_cast<std::size_t>(result.labels[i])].indices.push_back(
          indices ? (*indices)[i] : static_cast<pcl::index_t>(i));
  return clusters;
}

// The labelled points (the cloud, or its points at `indices`) as pcl::PointXYZL, label = the
// sphere; a dropped point has label kUnlabelled.
constexpr std::uint32_t kUnlabelled = std::numeric_limits<std::uint32_t>::max();
template <typename PointT>
pcl::PointCloud<pcl::PointXYZL> labelled_cloud(const pcl::PointCloud<PointT>& cloud,
                                               const Result& result,
                                               const pcl::Indices* indices = nullptr) {
  pcl::PointCloud<pcl::PointXYZL> labelled;
  for (std::size_t i = 0; i < result.labels.size(); ++i) {
    const PointT& p = point_taken(cloud, indices, i);
    pcl::PointXYZL point;
    point.x = p.x;
    point.y = p.y;
    point.z = p.z;
    point.label =
        result.labels[i] >= 0 ? static_cast<std::uint32_t>(result.labels[i]) : kUnlabelled;
    labelled.points.push_back(point);
  }
  // The whole of an organised cloud keeps its grid; anything else is one row.
  const bool whole = indices == nullptr;
  labelled.width = whole ? cloud.width : static_cast<std::uint32_t>(labelled.size());
  labelled.height = whole ? cloud.height : 1;
  labelled.is_dense = false;
  return labelled;
}

// A medial mesh in PCL types, for display. `centers` and `radii` list the spheres; `mesh` has
// the centres as its cloud and, as polygons, first every triangle (3 indices), then every edge
// (2 indices) — pcl::visualization::PCLVisualizer::addPolylineFromPolygonMesh draws them all as
// lines; keep the 3-index polygons for a surface view.
struct PclMedialMesh {
  pcl::PointCloud<pcl::PointXYZ> centers;
  std::vector<float> radii;
  pcl::PolygonMesh mesh;
};

inline PclMedialMesh to_pcl(const MedialMesh& medial) {
  PclMedialMesh result;
  for (const Sphere& s : medial.spheres) {
    result.centers.push_back(pcl::PointXYZ(static_cast<float>(s.center.x()),
                                           static_cast<float>(s.center.y()),
                                           static_cast<float>(s.center.z())));
    result.radii.push_back(static_cast<float>(s.radius));
  }
  pcl::toPCLPointCloud2(result.centers, result.mesh.cloud);
  for (const auto& face : medial.faces) {
    pcl::Vertices polygon;
    polygon.vertices.assign(face.begin(), face.end());
    result.mesh.polygons.push_back(polygon);
  }
  for (const auto& edge : medial.edges) {
    pcl::Vertices polygon;
    polygon.vertices.assign(edge.begin(), edge.end());
    result.mesh.polygons.push_back(polygon);
  }
  return result;
}

}  // namespace vmas
