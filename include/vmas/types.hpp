#pragma once
// Plain data shared by every stage: the input surface and the medial mesh.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <vector>

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

using Vec3 = Eigen::Vector3d;

struct Sphere {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
};

using Box = Eigen::AlignedBox3d;  // axis-aligned bounding box

inline Box bounding_box(const std::vector<Vec3>& points) {
  Box box;
  for (const Vec3& p : points) box.extend(p);
  return box;
}

// Length of the bounding box's diagonal; 0 for no points.
inline double diagonal_of(const Box& box) { return box.isEmpty() ? 0.0 : box.diagonal().norm(); }

// The middle value (the upper one of an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The input shape as read from disk: a triangle mesh when `faces` is non-empty, otherwise a
// point cloud. `normals` is empty (none given) or has one unit normal per point. `density` is
// empty (uniform) or has one value ≥ 0 per point: where the skeleton should be finer (4: about
// four times the spheres per area of 1; 0: as coarse as the budget allows; docs/design.md,
// "Density").
struct SurfaceInput {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;
  std::vector<std::array<int, 3>> faces;
  std::vector<double> density;

  bool is_mesh() const { return !faces.empty(); }
  bool has_normals() const { return !normals.empty(); }
};

// The skeleton: medial spheres plus edges and triangles between them (0-based indices).
struct MedialMesh {
  std::vector<Sphere> spheres;
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> faces;
};

}  // namespace vmas

#pragma GCC visibility pop
