#pragma once
// Triangle meshes built in code for the tests: exact geometry, fixed seeds, known medial axes.
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "vmas/types.hpp"

namespace vmas::test {

// Icosphere: the icosahedron subdivided `levels` times, projected on the sphere.
inline SurfaceInput icosphere(const Vec3& center, double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& v : p) v.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return midpoint[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& tri : f) {
      const int ab = middle(tri[0], tri[1]), bc = middle(tri[1], tri[2]),
                ca = middle(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  SurfaceInput s;
  for (const auto& v : p) s.points.push_back(center + radius * v);
  s.faces = f;
  return s;
}

// Torus around the z axis: tube radius `minor`, centre-circle radius `major`.
inline SurfaceInput torus(double major, double minor, int segments, int sides) {
  SurfaceInput s;
  for (int i = 0; i < segments; ++i) {
    const double u = 2.0 * M_PI * i / segments;
    for (int j = 0; j < sides; ++j) {
      const double v = 2.0 * M_PI * j / sides;
      s.points.emplace_back((major + minor * std::cos(v)) * std::cos(u),
                            (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return (i % segments) * sides + (j % sides); };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

// Capsule along the z axis: a cylinder of `radius` from z=0 to z=`length`, closed by hemispheres.
inline SurfaceInput capsule(double radius, double length, int rings, int sides) {
  SurfaceInput s;
  std::vector<std::pair<double, double>> profile;  // (z, ring radius)
  for (int i = 1; i < rings; ++i) {
    const double a = -M_PI / 2 + (M_PI / 2) * i / rings;
    profile.emplace_back(radius * std::sin(a), radius * std::cos(a));
  }
  const int body = std::max(2, static_cast<int>(std::round(length / (2 * M_PI * radius / sides))));
  for (int i = 0; i <= body; ++i) profile.emplace_back(length * i / body, radius);
  for (int i = 1; i < rings; ++i) {
    const double a = (M_PI / 2) * i / rings;
    profile.emplace_back(length + radius * std::sin(a), radius * std::cos(a));
  }
  s.points.emplace_back(0, 0, -radius);
  for (const auto& [z, r] : profile)
    for (int j = 0; j < sides; ++j) {
      const double v = 2.0 * M_PI * j / sides;
      s.points.emplace_back(r * std::cos(v), r * std::sin(v), z);
    }
  s.points.emplace_back(0, 0, length + radius);
  const int ring_count = static_cast<int>(profile.size());
  auto id = [&](int ring, int j) { return 1 + ring * sides + (j % sides); };
  for (int j = 0; j < sides; ++j) s.faces.push_back({0, id(0, j + 1), id(0, j)});
  for (int ring = 0; ring + 1 < ring_count; ++ring)
    for (int j = 0; j < sides; ++j) {
      s.faces.push_back({id(ring, j), id(ring, j + 1), id(ring + 1, j + 1)});
      s.faces.push_back({id(ring, j), id(ring + 1, j + 1), id(ring + 1, j)});
    }
  const int top = static_cast<int>(s.points.size()) - 1;
  for (int j = 0; j < sides; ++j)
    s.faces.push_back({top, id(ring_count - 1, j), id(ring_count - 1, j + 1)});
  return s;
}

// Three calls of `draw` as x, y and z, in this order. The order in which a call's arguments are
// evaluated is unspecified: g++ evaluated Vec3(draw(), draw(), draw()) right to left and clang++
// left to right, so that the same seed gave the two compilers different shapes.
template <class Draw>
Vec3 draw_xyz(Draw&& draw) {
  const double x = draw();
  const double y = draw();
  const double z = draw();
  return Vec3(x, y, z);
}

// Random samples with their exact outward normals, of shapes built in code (fixed seeds).
struct Sample {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;
  // The samples as a cloud, with their normals or without.
  SurfaceInput cloud(bool with_normals = true) const {
    SurfaceInput surface;
    surface.points = points;
    if (with_normals) surface.normals = normals;
    return surface;
  }
};

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  return draw_xyz([&] { return gauss(rng); }).normalized();
}

inline Sample sample_sphere(const Vec3& center, double radius, int count, unsigned seed) {
  std::mt19937 rng(seed);
  Sample s;
  for (int i = 0; i < count; ++i) {
    const Vec3 u = random_unit(rng);
    s.points.push_back(center + radius * u);
    s.normals.push_back(u);
  }
  return s;
}

// Axis-aligned box [0, size], faces sampled in proportion to their area.
inline Sample sample_box(const Vec3& size, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double areas[3] = {size.y() * size.z(), size.x() * size.z(), size.x() * size.y()};
  std::discrete_distribution<int> pick_axis(areas, areas + 3);
  Sample s;
  for (int i = 0; i < count; ++i) {
    const int axis = pick_axis(rng);
    const bool high = uniform(rng) < 0.5;
    Vec3 p = draw_xyz([&] { return uniform(rng); }).cwiseProduct(size);
    p[axis] = high ? size[axis] : 0.0;
    Vec3 n = Vec3::Zero();
    n[axis] = high ? 1.0 : -1.0;
    s.points.push_back(p);
    s.normals.push_back(n);
  }
  return s;
}

// Torus around the z axis, sampled uniformly by area (rejection on the tube angle).
inline Sample sample_torus(double major, double minor, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), uniform(0.0, 1.0);
  Sample s;
  while (static_cast<int>(s.points.size()) < count) {
    const double u = angle(rng), v = angle(rng);
    if (uniform(rng) * (major + minor) > major + minor * std::cos(v)) continue;
    const Vec3 radial(std::cos(u), std::sin(u), 0.0);
    const Vec3 n = std::cos(v) * radial + std::sin(v) * Vec3::UnitZ();
    s.points.push_back(major * radial + minor * n);
    s.normals.push_back(n);
  }
  return s;
}

inline Sample sample_ellipsoid(const Vec3& radii, int count, unsigned seed) {
  std::mt19937 rng(seed);
  Sample s;
  for (int i = 0; i < count; ++i) {
    const Vec3 p = random_unit(rng).cwiseProduct(radii);
    s.points.push_back(p);
    s.normals.push_back(p.cwiseQuotient(radii.cwiseProduct(radii)).normalized());
  }
  return s;
}

// Capsule along the z axis (as `capsule`), sampled uniformly by area.
inline Sample sample_capsule(double radius, double length, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double tube_area = 2.0 * M_PI * radius * length, caps_area = 4.0 * M_PI * radius * radius;
  Sample s;
  for (int i = 0; i < count; ++i) {
    if (uniform(rng) * (tube_area + caps_area) < tube_area) {
      const double angle = 2.0 * M_PI * uniform(rng);
      const Vec3 n(std::cos(angle), std::sin(angle), 0.0);
      s.points.push_back(radius * n + Vec3(0.0, 0.0, length * uniform(rng)));
      s.normals.push_back(n);
    } else {
      const Vec3 n = random_unit(rng);
      s.points.push_back(radius * n + Vec3(0.0, 0.0, n.z() > 0.0 ? length : 0.0));
      s.normals.push_back(n);
    }
  }
  return s;
}

// Gaussian noise of standard deviation `sigma` on every coordinate.
inline std::vector<Vec3> with_noise(std::vector<Vec3> points, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, sigma);
  for (Vec3& p : points) p += draw_xyz([&] { return gauss(rng); });
  return points;
}

inline double bounding_diagonal(const std::vector<Vec3>& points) {
  return diagonal_of(bounding_box(points));
}

}  // namespace vmas::test
