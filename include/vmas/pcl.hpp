#pragma once
// vmas with PCL types, header-only: for programs that already use PCL (vmas itself does not
// expose PCL). Link vmas::vmas and PCL's common component.
//
//   pcl::PointCloud<pcl::PointXYZ> cloud;
//   pcl::io::loadPCDFile("scan.pcd", cloud);          // organised clouds with NaNs are fine
//   vmas::Options options;
//   options.spheres = 40;
//   const vmas::Result result = vmas::skeletonize(cloud, options);
//   // result.labels[i]: the sphere of cloud[i] (-1 for NaN points, duplicates, outliers)
//   const vmas::PclMedialMesh display = vmas::to_pcl(result.medial_mesh);
#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <type_traits>
#include <vector>

#include "vmas/vmas.hpp"

namespace vmas {

// The points of `cloud` in order, NaN ones included (an organised cloud's "no return"), with
// normals for pcl::PointNormal (a point whose normal is not finite is then dropped as unusable;
// take pcl::PointXYZ to have normals estimated instead).
template <typename PointT>
SurfaceInput to_surface(const pcl::PointCloud<PointT>& cloud) {
  static_assert(std::is_same_v<PointT, pcl::PointXYZ> || std::is_same_v<PointT, pcl::PointNormal>,
                "vmas takes pcl::PointXYZ (normals estimated) or pcl::PointNormal (normals used)");
  SurfaceInput surface;
  surface.points.reserve(cloud.size());
  for (const PointT& p : cloud.points) {
    surface.points.emplace_back(p.x, p.y, p.z);
    if constexpr (std::is_same_v<PointT, pcl::PointNormal>)
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
