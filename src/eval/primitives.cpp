#include "eval/primitives.hpp"

namespace vmas {
namespace {

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Closest point by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5).
  const Vec3 ab = b - a, ac = c - a;
  if (!(ab.cross(ac).squaredNorm() > 1e-24 * ab.squaredNorm() * ac.squaredNorm())) {
    return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                     point_segment_distance(p, c, a)});
  }
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denominator = va + vb + vc;
  return (p - (a + ab * (vb / denominator) + ac * (vc / denominator))).norm();
}

double round_cone_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b) {
  return internal::Cone(a, b).signed_distance(p);
}

double slab_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b, const Sphere& c) {
  return internal::Slab(a, b, c).signed_distance(p);
}

bool slab_tangent_triangles(const Sphere& a, const Sphere& b, const Sphere& c,
                            std::array<std::array<Vec3, 3>, 2>& triangles) {
  const internal::Slab slab(a, b, c);
  if (slab.has_planes) triangles = slab.triangles;
  return slab.has_planes;
}

}  // namespace vmas
