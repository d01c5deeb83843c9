// What a pipeline does with vmas: a PCL cloud in, a skeleton out.
//   consumer make-organised OUT.pcd   writes an organised cloud of a capsule, with NaN holes
//   consumer INPUT.pcd OUTPUT.ply      skeletonizes INPUT with 40 spheres; checks the promises
#include <pcl/io/pcd_io.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vmas/io.hpp>
#include <vmas/pcl.hpp>
#include <vmas/skeletonizer.hpp>
#include <vmas/vmas.hpp>

namespace {

// A capsule (radius 0.3, axis along x, 2 long) as a 120 x 90 grid: columns go around the axis,
// rows from one pole to the other; every seventh cell is missing, as a scanner leaves them.
pcl::PointCloud<pcl::PointXYZ> organised_capsule() {
  const int width = 120, height = 90;
  const float radius = 0.3f, half_tube = 0.7f, quarter = 0.5f * static_cast<float>(M_PI);
  pcl::PointCloud<pcl::PointXYZ> cloud(width, height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int row = 0; row < height; ++row) {
    const float t = static_cast<float>(row) / (height - 1);
    float x = 0.0f, ring = radius;
    if (t < 0.2f || t > 0.8f) {  // a cap: polar angle from the pole
      const float polar = quarter * (t < 0.2f ? t : 1.0f - t) / 0.2f;
      x = (t < 0.2f ? -1.0f : 1.0f) * (half_tube + radius * std::cos(polar));
      ring = radius * std::sin(polar);
    } else {
      x = -half_tube + 2.0f * half_tube * (t - 0.2f) / 0.6f;
    }
    for (int column = 0; column < width; ++column) {
      const float angle = 4.0f * quarter * column / width;
      cloud.at(column, row) =
          (row * width + column) % 7 == 3
              ? pcl::PointXYZ(nan, nan, nan)
              : pcl::PointXYZ(x, ring * std::cos(angle), ring * std::sin(angle));
    }
  }
  return cloud;
}

int fail(const std::string& problem) {
  std::cerr << "consumer: " << problem << "\n";
  return 1;
}

// A Shape built by the library, read through this program's view of the public structs: the
// containers of a struct whose layout differs (compiler flags that change Eigen's alignment)
// read as garbage sizes.
bool shape_layout_agrees() {
  vmas::SurfaceInput cube;
  for (int i = 0; i < 8; ++i) cube.points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  cube.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  const vmas::Shape shape = vmas::build_shape(cube, vmas::ShapeOptions{});
  const double total = shape.quadric.size() == 8 ? shape.quadric[7].c + shape.quadric[0].A(3, 3)
                                                 : 0.0;
  return shape.size() == 8 && shape.quadric.size() == 8 && shape.area.size() == 8 &&
         std::isfinite(total) && total > 0.0 && std::abs(shape.total_area - 6.0) < 1e-12;
}

// A copy of `cloud` as another PCL point type (xyz only; normals, colour and intensity left as
// the type's default, NaN normals for the types that have them).
template <typename PointT>
pcl::PointCloud<PointT> as_type(const pcl::PointCloud<pcl::PointXYZ>& cloud) {
  pcl::PointCloud<PointT> copy(cloud.width, cloud.height);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    copy[i].x = cloud[i].x;
    copy[i].y = cloud[i].y;
    copy[i].z = cloud[i].z;
    if constexpr (pcl::traits::has_normal_v<PointT>)
      copy[i].normal_x = copy[i].normal_y = copy[i].normal_z =
          std::numeric_limits<float>::quiet_NaN();
  }
  return copy;
}

// The point types PCL users hold, shared pointers and an index subset: the same points give the
// same skeleton whatever the type, and the labels come back in PCL's forms.
std::string check_point_types(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                              const vmas::Options& options, const vmas::Result& reference) {
  const auto same = [&](const vmas::Result& r) {
    if (r.labels.size() != reference.labels.size()) return false;
    for (std::size_t i = 0; i < r.medial_mesh.spheres.size(); ++i)
      if (r.medial_mesh.spheres[i].center != reference.medial_mesh.spheres[i].center) return false;
    return r.medial_mesh.spheres.size() == reference.medial_mesh.spheres.size();
  };
  if (!same(vmas::skeletonize(as_type<pcl::PointXYZRGB>(cloud), options)))
    return "PointXYZRGB differs from PointXYZ";
  if (!same(vmas::skeletonize(as_type<pcl::PointXYZI>(cloud), options)))
    return "PointXYZI differs from PointXYZ";
  const pcl::PointCloud<pcl::PointXYZ>::ConstPtr shared = cloud.makeShared();
  if (!same(vmas::skeletonize(shared, options))) return "ConstPtr differs from the cloud";
  // NaN normals are estimated: every finite point keeps its place and gets a label.
  for (const vmas::Result& r :
       {vmas::skeletonize(as_type<pcl::PointNormal>(cloud), options),
        vmas::skeletonize(as_type<pcl::PointXYZRGBNormal>(cloud), options)}) {
    if (r.medial_mesh.spheres.size() != 40) return "a type with NaN normals: not 40 spheres";
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (std::isfinite(cloud[i].x) && r.labels[i] < 0 && reference.labels[i] >= 0)
        return "a point with a NaN normal lost its label";
  }
  pcl::Indices finite;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (std::isfinite(cloud[i].x) && cloud[i].x < 0.5f) finite.push_back(static_cast<int>(i));
  const vmas::Result part = vmas::skeletonize(shared, finite, options);
  if (part.labels.size() != finite.size()) return "labels of an index subset: wrong count";
  std::size_t clustered = 0;
  for (const pcl::PointIndices& c : vmas::clusters_of(part, &finite))
    for (pcl::index_t i : c.indices) {
      if (!(cloud[static_cast<std::size_t>(i)].x < 0.5f))
        return "clusters_of: index outside the subset";
      ++clustered;
    }
  std::size_t labelled = 0;
  for (int label : part.labels) labelled += label >= 0;
  if (clustered != labelled) return "clusters_of does not hold every labelled point";
  const pcl::PointCloud<pcl::PointXYZL> whole = vmas::labelled_cloud(cloud, reference);
  if (whole.width != cloud.width || whole.height != cloud.height)
    return "labelled_cloud lost the organised grid";
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if ((reference.labels[i] < 0) != (whole[i].label == vmas::kUnlabelled))
      return "labelled_cloud: labels differ";
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "make-organised") {
    return pcl::io::savePCDFileBinary(argv[2], organised_capsule()) == 0 ? 0 : 1;
  }
  if (!shape_layout_agrees()) return fail("vmas::Shape from build_shape reads wrong here (ABI)");
  if (argc != 3) return fail("usage: consumer INPUT.pcd OUTPUT.ply | make-organised OUT.pcd");
  pcl::PointCloud<pcl::PointXYZ> cloud;
  if (pcl::io::loadPCDFile(argv[1], cloud) != 0) return fail(std::string("cannot read ") + argv[1]);
  std::cout << "vmas " << vmas::version() << ": " << cloud.width << " x " << cloud.height
            << " cloud (organised: " << (cloud.isOrganized() ? "yes" : "no") << ")\n";
  vmas::Options options;
  options.run.target.spheres = 40;
  const vmas::Result result = vmas::skeletonize(cloud, options);
  vmas::write_medial_mesh(argv[2], result.medial_mesh);
  if (result.labels.size() != cloud.size()) return fail("labels.size() != cloud.size()");
  if (result.medial_mesh.spheres.size() != 40) return fail("not 40 spheres");
  std::size_t nan_points = 0, unlabelled_nan = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!std::isfinite(cloud[i].x)) {
      ++nan_points;
      unlabelled_nan += result.labels[i] == -1;
    }
  if (unlabelled_nan != nan_points) return fail("a NaN point has a label");
  const vmas::PclMedialMesh display = vmas::to_pcl(result.medial_mesh);
  if (display.centers.size() != 40 ||
      display.mesh.polygons.size() !=
          result.medial_mesh.faces.size() + result.medial_mesh.edges.size())
    return fail("to_pcl lost spheres or polygons");
  const std::string types = check_point_types(cloud, options, result);
  if (!types.empty()) return fail(types);
  std::cout << "ok: " << result.medial_mesh.spheres.size() << " spheres, "
            << result.medial_mesh.edges.size() << " edges, " << result.labels.size() << " labels ("
            << nan_points << " NaN points unlabelled), " << result.warnings.size() << " warnings\n";
  return 0;
}
