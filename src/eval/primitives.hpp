#pragma once
// The solids of the reconstruction (paper §4): a sphere, the round cone of two spheres (their
// convex hull) and the slab of three (the convex hull of three, bounded by three cones and the
// two triangles tangent to all three spheres), with their exact signed distances.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "vmas/types.hpp"

namespace vmas {

// Euclidean distance from p to the triangle abc (degenerate triangles allowed).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Exact signed distance to the round cone spanned by two spheres (negative inside). When one
// sphere contains the other the cone is the bigger sphere.
double round_cone_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b);

// Signed distance to the slab spanned by three spheres: outside, the exact distance; inside, a
// negative value whose magnitude is at most the depth (the depth inside the deepest interpolated
// sphere), so its sign is an exact inside test.
double slab_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b, const Sphere& c);

// The two triangles tangent to all three spheres (vertices are the tangent points, in the order
// a, b, c). False when they do not exist: collinear centres, or one sphere inside another.
bool slab_tangent_triangles(const Sphere& a, const Sphere& b, const Sphere& c,
                            std::array<std::array<Vec3, 3>, 2>& triangles);

namespace internal __attribute__((visibility("hidden"))) {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

inline Box sphere_box(const Vec3& center, double radius) {
  const Vec3 extent = Vec3::Constant(radius);
  return Box(center - extent, center + extent);
}

// The convex hull of two spheres. When one contains the other it is the bigger sphere, stored in
// c1/r1 with `is_sphere` set.
struct Cone {
  Vec3 c1, c2, axis;
  double r1 = 0.0, r2 = 0.0, h = 0.0;
  double a = 1.0, b = 0.0;  // (cos, sin) of the lateral surface's slope against the axis
  bool is_sphere = false;

  Cone(const Sphere& s1, const Sphere& s2)
      : c1(s1.center), c2(s2.center), r1(s1.radius), r2(s2.radius), h((c2 - c1).norm()) {
    if (h <= std::abs(r1 - r2)) {
      is_sphere = true;
      if (r2 > r1) {
        c1 = c2;
        r1 = r2;
      }
      return;
    }
    axis = (c2 - c1) / h;
    b = (r1 - r2) / h;
    a = std::sqrt(1.0 - b * b);
  }

  // In the (axial x, radial y) half-plane the boundary is circle 1, the tangent segment and
  // circle 2; the normal of the segment is (b, a), which splits the plane into three regions.
  double signed_distance(const Vec3& p) const {
    const Vec3 q = p - c1;
    if (is_sphere) return q.norm() - r1;
    const double x = q.dot(axis);
    const double y = (q - x * axis).norm();
    const double k = a * x - b * y;
    if (k < 0.0) return q.norm() - r1;
    if (k > a * h) return (p - c2).norm() - r2;
    return a * y + b * x - r1;
  }

  Box box() const {
    Box box = sphere_box(c1, r1);
    if (!is_sphere) box.extend(sphere_box(c2, r2));
    return box;
  }
};

// The convex hull of three spheres, i.e. the union of the spheres interpolated linearly over the
// triangle. Distance to it = min over the triangle of |p - c(t)| - r(t), a convex function of t:
// its minimum is either the interior critical point, where it equals the distance to a tangent
// plane, or on an edge, where it is the cone's distance.
struct Slab {
  std::array<Cone, 3> cones;
  bool has_planes = false;
  Vec3 c0, e1, e2, normal, gradient;  // gradient: of the radius, interpolated over the plane
  double r0 = 0.0, s = 0.0;           // s = sqrt(1 - |gradient|^2)
  double d00 = 0.0, d01 = 0.0, d11 = 0.0, det = 0.0;
  std::array<std::array<Vec3, 3>, 2> triangles;

  Slab(const Sphere& s0, const Sphere& s1, const Sphere& s2)
      : cones{Cone(s0, s1), Cone(s1, s2), Cone(s2, s0)},
        c0(s0.center),
        e1(s1.center - s0.center),
        e2(s2.center - s0.center),
        r0(s0.radius) {
    d00 = e1.squaredNorm();
    d01 = e1.dot(e2);
    d11 = e2.squaredNorm();
    const Vec3 cross = e1.cross(e2);
    det = cross.squaredNorm();  // = d00 * d11 - d01^2, without the cancellation
    // (Nearly) collinear centres: the minimum is on an edge.
    if (!(det > 1e-12 * d00 * d11)) return;
    const double dr1 = s1.radius - r0, dr2 = s2.radius - r0;
    gradient = ((d11 * dr1 - d01 * dr2) * e1 + (d00 * dr2 - d01 * dr1) * e2) / det;
    const double g2 = gradient.squaredNorm();
    // |gradient| >= 1: one sphere is inside (or internally tangent to) another, no tangent plane.
    if (g2 >= 1.0) return;
    has_planes = true;
    s = std::sqrt(1.0 - g2);
    normal = cross.normalized();
    const std::array<const Sphere*, 3> spheres{&s0, &s1, &s2};
    for (int i = 0; i < 3; ++i) {
      const Sphere& sphere = *spheres[i];
      triangles[0][i] = sphere.center + sphere.radius * (s * normal - gradient);
      triangles[1][i] = sphere.center + sphere.radius * (-s * normal - gradient);
    }
  }

  double signed_distance(const Vec3& p) const {
    if (has_planes) {
      const double height = (p - c0).dot(normal);
      const Vec3 in_plane = p - height * normal;
      const Vec3 v = in_plane + gradient * (std::abs(height) / s) - c0;
      const double d20 = v.dot(e1), d21 = v.dot(e2);
      const double u = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
      if (u >= 0.0 && w >= 0.0 && u + w <= 1.0) {
        return s * std::abs(height) - (r0 + gradient.dot(in_plane - c0));
      }
    }
    return std::min(
        {cones[0].signed_distance(p), cones[1].signed_distance(p), cones[2].signed_distance(p)});
  }

  Box box() const { return cones[0].box().extend(cones[1].box()).extend(cones[2].box()); }
};

}  // namespace internal
}  // namespace vmas
