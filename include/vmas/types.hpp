#pragma once
// Plain data shared by every stage: the input surface, the medial mesh, and the spherical
// quadric error metric (Sqem) the method measures spheres against.
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

// Spherical quadric error metric (Thiery et al. 2013; paper eq. 3): the squared distance from a
// sphere s = (q, r) to the plane {p, n}⊥, written as Q(s) = ½ sᵀAs − bᵀs + c with
// A = 2ññᵀ, b = 2(n·p)ñ, c = (n·p)², ñ = (n, 1). Quadrics add, so a sum of planes is one quadric.
// Unaligned storage: the layout of an aligned 4-vector or 4x4 matrix depends on the compiler
// flags (alignment 16 for generic x86-64, 32 with AVX, 64 with AVX-512), so a program built with
// -march=native would see another Sqem, and another std::vector<Sqem>, than the library.
using Vec4 = Eigen::Matrix<double, 4, 1, Eigen::DontAlign>;
using Mat4 = Eigen::Matrix<double, 4, 4, Eigen::DontAlign>;

inline Vec4 to_vec4(const Sphere& s) {
  return Vec4(s.center.x(), s.center.y(), s.center.z(), s.radius);
}
inline Sphere to_sphere(const Vec4& s) { return Sphere{s.head<3>(), s.w()}; }

struct Sqem {
  Mat4 A = Mat4::Zero();
  Vec4 b = Vec4::Zero();
  double c = 0.0;

  // The plane through `point` with unit normal `normal`, weighted by `weight`.
  static Sqem plane(const Vec3& point, const Vec3& normal, double weight = 1.0) {
    const Vec4 n_tilde(normal.x(), normal.y(), normal.z(), 1.0);
    const double offset = normal.dot(point);
    Sqem q;
    q.A = (2.0 * weight) * n_tilde * n_tilde.transpose();
    q.b = (2.0 * weight * offset) * n_tilde;
    q.c = weight * offset * offset;
    return q;
  }

  double operator()(const Vec4& s) const { return 0.5 * s.dot(A * s) - b.dot(s) + c; }
  double operator()(const Sphere& s) const { return (*this)(to_vec4(s)); }

  Sqem& operator+=(const Sqem& other) {
    A += other.A;
    b += other.b;
    c += other.c;
    return *this;
  }
  // += weight × other.
  Sqem& add(const Sqem& other, double weight) {
    A += weight * other.A;
    b += weight * other.b;
    c += weight * other.c;
    return *this;
  }
};

}  // namespace vmas

#pragma GCC visibility pop
