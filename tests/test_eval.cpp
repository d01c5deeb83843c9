#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "eval/envelope.hpp"
#include "shared_data.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Vec3> fibonacci_directions(int count) {
  std::vector<Vec3> directions(count);
  const double golden_angle = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count, rho = std::sqrt(1.0 - z * z);
    directions[i] = Vec3(rho * std::cos(golden_angle * i), rho * std::sin(golden_angle * i), z);
  }
  return directions;
}

// Brute force for a convex hull of spheres: sd(p) = max over unit n of n.p - h(n), with the
// support function h(n) = max_i n.c_i + r_i (exact inside and outside), over dense directions.
// h has ridges where two spheres support the same plane (the cones' lateral normals), so those
// circles of directions are sampled too, and the tangent planes' normals are added.
std::vector<Vec3> hull_directions(const std::vector<Sphere>& spheres) {
  std::vector<Vec3> directions = fibonacci_directions(40000);
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    for (std::size_t j = i + 1; j < spheres.size(); ++j) {
      const Vec3 d = spheres[j].center - spheres[i].center;
      const double b = (spheres[i].radius - spheres[j].radius) / d.norm();
      if (std::abs(b) >= 1.0) continue;
      const Vec3 axis = d.normalized(), u = axis.unitOrthogonal(), v = axis.cross(u);
      for (int k = 0; k < 20000; ++k) {
        const double angle = 2 * kPi * k / 20000;
        directions.push_back(b * axis +
                             std::sqrt(1 - b * b) * (std::cos(angle) * u + std::sin(angle) * v));
      }
    }
  }
  std::array<std::array<Vec3, 3>, 2> triangles;
  if (spheres.size() == 3 &&
      slab_tangent_triangles(spheres[0], spheres[1], spheres[2], triangles)) {
    for (const auto& t : triangles) {
      const Vec3 n = (t[0] - spheres[0].center).normalized();  // radius direction at the contact
      directions.push_back(n);
    }
  }
  return directions;
}

double hull_signed_distance(const Vec3& p, const std::vector<Sphere>& spheres) {
  double best = -std::numeric_limits<double>::infinity();
  for (const Vec3& n : hull_directions(spheres)) {
    double support = -std::numeric_limits<double>::infinity();
    for (const Sphere& s : spheres) support = std::max(support, n.dot(s.center) + s.radius);
    best = std::max(best, n.dot(p) - support);
  }
  return best;
}

struct Random {
  std::mt19937 rng;
  explicit Random(unsigned seed) : rng(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  Vec3 point(double extent) {
    return test::draw_xyz([&] { return uniform(-extent, extent); });
  }
  Sphere sphere() { return {point(1.0), uniform(0.05, 0.6)}; }
};

// Unit sphere approximated by a subdivided icosahedron (vertices on the sphere).
// Brute force outside a hull of spheres: the distance to the union of the interpolated spheres
// c(t), r(t) over a dense grid of barycentric coordinates (two or three spheres).
double interpolated_distance(const Vec3& p, const std::vector<Sphere>& spheres, int steps) {
  double best = std::numeric_limits<double>::infinity();
  const int k_steps = spheres.size() == 3 ? steps : 0;
  for (int i = 0; i <= steps; ++i) {
    for (int k = 0; k <= std::min(k_steps, steps - i); ++k) {
      const double t1 = double(i) / steps, t2 = double(k) / steps, t0 = 1.0 - t1 - t2;
      Vec3 center = t0 * spheres[0].center + t1 * spheres[1].center;
      double radius = t0 * spheres[0].radius + t1 * spheres[1].radius;
      if (spheres.size() == 3) {
        center += t2 * spheres[2].center;
        radius += t2 * spheres[2].radius;
      }
      best = std::min(best, (p - center).norm() - radius);
    }
  }
  return best;
}

// Points around a hull of spheres: near its surface (inside and outside) and farther away.
std::vector<Vec3> points_around(const std::vector<Sphere>& spheres, Random& random, int count) {
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const Sphere& s = spheres[i % spheres.size()];
    const Sphere& t = spheres[(i + 1) % spheres.size()];
    const double w = random.uniform(0.0, 1.0), scale = i % 4 == 0 ? 4.0 : 1.5;
    const Vec3 direction = random.point(1.0).normalized();
    points.push_back((1 - w) * s.center + w * t.center +
                     random.uniform(0.0, scale) * ((1 - w) * s.radius + w * t.radius) * direction);
  }
  return points;
}

TEST(EvalGeometry, RoundConeMatchesBruteForce) {
  Random random(7);
  int inside = 0;
  for (int config = 0; config < 20; ++config) {
    const Sphere a = random.sphere(), b = random.sphere();
    for (const Vec3& p : points_around({a, b}, random, 15)) {
      const double value = round_cone_signed_distance(p, a, b);
      EXPECT_NEAR(value, round_cone_signed_distance(p, b, a), 1e-12);
      // Exact on both sides; finitely many directions underestimate by O(spacing^2).
      const double support = hull_signed_distance(p, {a, b});
      EXPECT_GE(value, support - 1e-12);
      EXPECT_LE(value, support + 5e-4);
      if (value > 0.0) {
        EXPECT_NEAR(value, interpolated_distance(p, {a, b}, 20000), 1e-6);
      }
      inside += value < 0.0;
    }
  }
  EXPECT_GT(inside, 60);  // the interior formula was exercised
}

TEST(EvalGeometry, SlabMatchesBruteForceOutsideAndSignInside) {
  Random random(11);
  int inside = 0, with_planes = 0;
  for (int config = 0; config < 20; ++config) {
    const Sphere a = random.sphere(), b = random.sphere(), c = random.sphere();
    std::array<std::array<Vec3, 3>, 2> triangles;
    with_planes += slab_tangent_triangles(a, b, c, triangles);
    for (const Vec3& p : points_around({a, b, c}, random, 15)) {
      const double value = slab_signed_distance(p, a, b, c);
      EXPECT_NEAR(value, slab_signed_distance(p, c, a, b), 1e-12);
      const double support = hull_signed_distance(p, {a, b, c});
      EXPECT_GE(value, support - 1e-12);  // inside: the magnitude is at most the depth
      if (support > 5e-4) {
        EXPECT_LE(value, support + 5e-4);
        EXPECT_NEAR(value, interpolated_distance(p, {a, b, c}, 300), 1e-4);
      } else if (support < -5e-4) {
        EXPECT_LT(value, 0.0);
        ++inside;
      }
    }
  }
  EXPECT_GT(inside, 60);
  EXPECT_GT(with_planes, 10);
}

TEST(EvalGeometry, TangentTrianglesTouchAllThreeSpheres) {
  Random random(13);
  int checked = 0;
  for (int config = 0; config < 50; ++config) {
    const std::array<Sphere, 3> s{random.sphere(), random.sphere(), random.sphere()};
    std::array<std::array<Vec3, 3>, 2> triangles;
    if (!slab_tangent_triangles(s[0], s[1], s[2], triangles)) continue;
    ++checked;
    for (const auto& t : triangles) {
      // The plane's outward normal points away from the medial triangle.
      Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
      if (normal.dot(s[0].center - t[0]) > 0.0) normal = -normal;
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR((t[i] - s[i].center).norm(), s[i].radius, 1e-9);      // on sphere i
        EXPECT_NEAR(normal.dot(s[i].center - t[0]), -s[i].radius, 1e-9);  // plane tangent to it
        EXPECT_NEAR(slab_signed_distance(t[i], s[0], s[1], s[2]), 0.0, 1e-9);
      }
      EXPECT_NEAR(slab_signed_distance((t[0] + t[1] + t[2]) / 3 + 0.1 * normal, s[0], s[1], s[2]),
                  0.1, 1e-9);
    }
  }
  EXPECT_GT(checked, 10);
}

TEST(EvalGeometry, DegenerateConesAndSlabs) {
  const Sphere big{Vec3(0, 0, 0), 1.0}, small{Vec3(0.3, 0, 0), 0.5}, far{Vec3(3, 0, 0), 0.5};
  const Vec3 p(0.2, 1.7, -0.4);
  // One sphere inside the other: the cone is the bigger sphere.
  EXPECT_NEAR(round_cone_signed_distance(p, big, small), p.norm() - 1.0, 1e-12);
  EXPECT_NEAR(round_cone_signed_distance(p, small, big), p.norm() - 1.0, 1e-12);
  EXPECT_NEAR(round_cone_signed_distance(p, big, big), p.norm() - 1.0, 1e-12);
  // Equal radii: a capsule, distance to the segment minus the radius.
  const Sphere left{Vec3(0, 0, 0), 0.5}, right{Vec3(2, 0, 0), 0.5};
  EXPECT_NEAR(round_cone_signed_distance(Vec3(1, 0.2, 0), left, right), -0.3, 1e-12);
  EXPECT_NEAR(round_cone_signed_distance(Vec3(2.5, 1, 0), left, right), std::hypot(0.5, 1.0) - 0.5,
              1e-12);

  std::array<std::array<Vec3, 3>, 2> triangles;
  // Collinear centres: no tangent triangle, the slab is the union of its cones.
  const Sphere middle{Vec3(1.5, 0, 0), 0.7};
  EXPECT_FALSE(slab_tangent_triangles(left, middle, far, triangles));
  for (const Vec3& q : {Vec3(1.5, 0.9, 0.1), Vec3(0.7, 0.3, 0), Vec3(4, 1, 1)}) {
    const double cones = std::min({round_cone_signed_distance(q, left, middle),
                                   round_cone_signed_distance(q, middle, far),
                                   round_cone_signed_distance(q, left, far)});
    EXPECT_NEAR(slab_signed_distance(q, left, middle, far), cones, 1e-12);
  }
  // One sphere inside another: no tangent triangle either.
  EXPECT_FALSE(slab_tangent_triangles(big, small, far, triangles));
  EXPECT_NEAR(slab_signed_distance(Vec3(1.5, 2, 0), big, small, far),
              round_cone_signed_distance(Vec3(1.5, 2, 0), big, far), 1e-12);
  // Equal radii: the tangent planes are parallel to the centres' plane at distance r.
  const Sphere top{Vec3(1, 2, 0), 0.5};
  ASSERT_TRUE(slab_tangent_triangles(left, right, top, triangles));
  EXPECT_NEAR(std::abs(triangles[0][0].z()), 0.5, 1e-12);
  EXPECT_NEAR(slab_signed_distance(Vec3(1, 0.5, 2), left, right, top), 1.5, 1e-12);
  EXPECT_NEAR(slab_signed_distance(Vec3(1, 0.5, 0.1), left, right, top), -0.4, 1e-12);
}

TEST(EvalGeometry, PointTriangleDistance) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_NEAR(point_triangle_distance(Vec3(0.2, 0.2, 0.5), a, b, c), 0.5, 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(-1, -1, 0), a, b, c), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(1, 1, 0), a, b, c), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(0.5, -2, 0), a, b, c), 2.0, 1e-12);
  // Degenerate (collinear) triangle: distance to its longest segment.
  EXPECT_NEAR(point_triangle_distance(Vec3(0.5, 1, 0), a, b, Vec3(0.5, 0, 0)), 1.0, 1e-12);
  EXPECT_NEAR(point_triangle_distance(Vec3(3, 0, 0), a, a, a), 3.0, 1e-12);
}

TEST(Eval, SphereAgainstItsMedialSphereIsAlmostExact) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  MedialMesh medial;
  medial.spheres = {{Vec3::Zero(), 1.0}};
  const EvalResult result = evaluate(mesh, medial);
  EXPECT_NEAR(result.diagonal, 2.0 * std::sqrt(3.0), 0.05);
  EXPECT_LT(result.hausdorff, 3e-3);  // chordal error of the tessellation
  EXPECT_LT(result.percent(result.hausdorff), 0.1);
  ASSERT_EQ(result.vertex_error.size(), mesh.points.size());
  for (double e : result.vertex_error) EXPECT_NEAR(e, 0.0, 1e-12);  // vertices lie on the sphere
  EXPECT_EQ(result.surface_sample_count, 2 * mesh.points.size());
  EXPECT_GT(result.boundary_sample_count, 500u);
}

TEST(Eval, ShiftedSphereGivesTheShift) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  MedialMesh medial;
  medial.spheres = {{Vec3(0.1, 0, 0), 1.0}};
  const EvalResult result = evaluate(mesh, medial);
  EXPECT_NEAR(result.surface_to_medial_max, 0.1, 3e-3);
  EXPECT_NEAR(result.medial_to_surface_max, 0.1, 3e-3);
  EXPECT_NEAR(result.hausdorff, 0.1, 3e-3);
  EXPECT_GT(result.surface_to_medial_mean, 0.03);  // mean |x| over the sphere is 0.05
  EXPECT_LT(result.surface_to_medial_mean, 0.07);
}

// A dense mesh measured from a voxel subset of its vertices: about as many samples as asked,
// and maxima close to those from every vertex (the subset is spread over the whole surface).
TEST(Eval, ASubsetOfTheVerticesGivesAboutTheSameMaxima) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 5);  // 10 242 vertices
  MedialMesh medial;
  medial.spheres = {{Vec3(0.1, 0.05, 0), 0.9}, {Vec3(-0.2, 0, 0.1), 0.8}};
  medial.edges = {{0, 1}};
  EvalOptions options;
  options.surface_samples = 0;
  options.maxima_only = true;
  const EvalResult every = evaluate(mesh, medial, options);
  EXPECT_EQ(every.surface_sample_count, mesh.points.size());
  options.max_input_points = 1000;
  const EvalResult subset = evaluate(mesh, medial, options);
  EXPECT_LE(subset.surface_sample_count, 1000u);
  EXPECT_GE(subset.surface_sample_count, 800u);
  EXPECT_NEAR(subset.surface_to_medial_max, every.surface_to_medial_max, 0.01);
  EXPECT_LE(subset.surface_to_medial_max, every.surface_to_medial_max);
  EXPECT_DOUBLE_EQ(subset.medial_to_surface_max, every.medial_to_surface_max);  // the faces
}

TEST(Eval, CapsuleAgainstItsRoundCone) {
  const SurfaceInput mesh = test::capsule(0.5, 2.0, 16, 64);
  MedialMesh medial;
  medial.spheres = {{Vec3(0, 0, 0), 0.5}, {Vec3(0, 0, 2), 0.5}};
  medial.edges = {{0, 1}};
  const EvalResult result = evaluate(mesh, medial);
  EXPECT_LT(result.hausdorff, 2e-3);
  // Without the edge the waist is far from both spheres' boundaries, and the inner halves of the
  // spheres are half a radius from the cylinder wall.
  medial.edges.clear();
  const EvalResult spheres_only = evaluate(mesh, medial);
  EXPECT_NEAR(spheres_only.surface_to_medial_max, std::sqrt(1.25) - 0.5, 0.01);
  EXPECT_NEAR(spheres_only.medial_to_surface_max, 0.5, 0.01);
}

TEST(Eval, ASparseCloudWithNormalsIsMeasuredAcrossItsDiscs) {
  // 300 random points of the unit sphere, with their normals: a random sampling's widest gap
  // puts points of the sphere 0.37 from the nearest sample, while the sphere itself is the exact
  // reconstruction.
  std::mt19937 random(7);
  std::normal_distribution<double> gaussian;
  SurfaceInput cloud;
  for (int i = 0; i < 300; ++i) {
    const Vec3 p = Vec3(gaussian(random), gaussian(random), gaussian(random)).normalized();
    cloud.points.push_back(p);
    cloud.normals.push_back(p);
  }
  MedialMesh exact;
  exact.spheres = {{Vec3::Zero(), 1.0}};
  EvalOptions to_points;
  to_points.boundary_spacing = 0.01;
  EvalOptions to_discs = to_points;
  to_discs.cloud_as_discs = true;
  const EvalResult gaps = evaluate(cloud, exact, to_points);
  const EvalResult across = evaluate(cloud, exact, to_discs);
  EXPECT_GT(gaps.medial_to_surface_max, 0.3);
  // The discs close all but the widest gaps' middles (0.07).
  EXPECT_LT(across.medial_to_surface_max, 0.25 * gaps.medial_to_surface_max);
  EXPECT_EQ(across.surface_to_medial_max, gaps.surface_to_medial_max);  // the other side as is
  // A reconstruction reaching past the surface is measured as far as it reaches.
  MedialMesh swollen;
  swollen.spheres = {{Vec3::Zero(), 1.1}};
  EXPECT_NEAR(evaluate(cloud, swollen, to_discs).medial_to_surface_max, 0.1, 0.01);
  // Without normals the points are all there is.
  cloud.normals.clear();
  EXPECT_EQ(evaluate(cloud, exact, to_discs).medial_to_surface_max, gaps.medial_to_surface_max);
}

TEST(Eval, PointInsideAPrimitiveMeasuresToItsBoundary) {
  // A cloud of two points inside a sphere: each is as far from the reconstruction as from the
  // sphere's boundary (the distance to a boundary, not to the solid).
  SurfaceInput cloud;
  cloud.points = {Vec3(0.2, 0, 0), Vec3(-0.5, 0, 0)};
  MedialMesh medial;
  medial.spheres = {{Vec3::Zero(), 1.0}};
  EvalOptions options;
  options.boundary_spacing = 0.01;  // the diagonal is small against the sphere
  const EvalResult result = evaluate(cloud, medial, options);
  ASSERT_EQ(result.vertex_error.size(), 2u);
  EXPECT_NEAR(result.vertex_error[0], 0.8, 1e-12);
  EXPECT_NEAR(result.vertex_error[1], 0.5, 1e-12);
  EXPECT_EQ(result.surface_sample_count, 2u);  // clouds get no extra samples
  // The sphere point farthest from both points is equidistant from them, at x = -0.15.
  EXPECT_NEAR(result.medial_to_surface_max, std::sqrt(1.1), 0.01);
}

// A random medial mesh with edges and faces (some degenerate) around a sphere shape.
MedialMesh random_medial(unsigned seed) {
  Random random(seed);
  MedialMesh medial;
  for (int i = 0; i < 25; ++i)
    medial.spheres.push_back({random.point(0.7), random.uniform(0.05, 0.4)});
  medial.spheres.push_back({medial.spheres[0].center, 0.5 * medial.spheres[0].radius});
  std::uniform_int_distribution<int> index(0, 25);
  for (int i = 0; i < 30; ++i) {
    const int a = index(random.rng), b = index(random.rng);
    if (a != b) medial.edges.push_back({a, b});
  }
  for (int i = 0; i < 15; ++i) {
    const int a = index(random.rng), b = index(random.rng), c = index(random.rng);
    if (a != b && b != c && a != c) medial.faces.push_back({a, b, c});
  }
  medial.faces.push_back({0, 25, 1});  // sphere 25 inside sphere 0
  return medial;
}

TEST(Eval, AcceleratedDistancesEqualBruteForce) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  const MedialMesh medial = random_medial(5);
  EvalOptions options;
  options.boundary_spacing = 0.01;
  const EvalResult result = evaluate(mesh, medial, options);

  // Surface -> medial: min over every boundary piece, all pairs.
  std::vector<std::array<int, 2>> edges = medial.edges;
  for (const auto& f : medial.faces)
    edges.insert(edges.end(), {{f[0], f[1]}, {f[1], f[2]}, {f[2], f[0]}});
  std::vector<std::array<Vec3, 3>> triangles;
  for (const auto& f : medial.faces) {
    std::array<std::array<Vec3, 3>, 2> pair;
    if (slab_tangent_triangles(medial.spheres[f[0]], medial.spheres[f[1]], medial.spheres[f[2]],
                               pair)) {
      triangles.insert(triangles.end(), pair.begin(), pair.end());
    }
  }
  ASSERT_GT(triangles.size(), 10u);
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const Vec3& p = mesh.points[v];
    double best = std::numeric_limits<double>::infinity();
    for (const Sphere& s : medial.spheres)
      best = std::min(best, std::abs((p - s.center).norm() - s.radius));
    for (const auto& e : edges) {
      best = std::min(best, std::abs(round_cone_signed_distance(p, medial.spheres[e[0]],
                                                                medial.spheres[e[1]])));
    }
    for (const auto& t : triangles)
      best = std::min(best, point_triangle_distance(p, t[0], t[1], t[2]));
    EXPECT_NEAR(result.vertex_error[v], best, 1e-12) << "vertex " << v;
  }

  // Medial -> surface: every visible sample against every input triangle.
  const std::vector<Vec3> samples =
      envelope_samples(medial, options.boundary_spacing * result.diagonal,
                       options.inside_tolerance * result.diagonal);
  ASSERT_EQ(samples.size(), result.boundary_sample_count);
  double max = 0.0, sum = 0.0;
  for (const Vec3& q : samples) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& f : mesh.faces) {
      best = std::min(best, point_triangle_distance(q, mesh.points[f[0]], mesh.points[f[1]],
                                                    mesh.points[f[2]]));
    }
    max = std::max(max, best);
    sum += best;
    // Visible: inside no primitive (beyond the tolerance).
    for (const Sphere& s : medial.spheres) ASSERT_GT((q - s.center).norm() - s.radius, -1e-5);
    for (const auto& e : edges) {
      ASSERT_GT(round_cone_signed_distance(q, medial.spheres[e[0]], medial.spheres[e[1]]), -1e-5);
    }
    for (const auto& f : medial.faces) {
      ASSERT_GT(
          slab_signed_distance(q, medial.spheres[f[0]], medial.spheres[f[1]], medial.spheres[f[2]]),
          -1e-5);
    }
  }
  EXPECT_NEAR(result.medial_to_surface_mean, sum / samples.size(), 1e-12);
  // The maximum is refined around the samples: at least theirs, at most a spacing more (the
  // distance is 1-Lipschitz).
  EXPECT_GE(result.medial_to_surface_max, max);
  EXPECT_LE(result.medial_to_surface_max, max + options.boundary_spacing * result.diagonal);
}

// The medial -> surface side sample by sample: evaluate() exposes the visible boundary samples
// and their distances to the input, and `vmas eval --medial-errors` writes exactly those.
TEST(Eval, BoundarySamplesAndTheirDistancesAreExposed) {
  SurfaceInput cloud = test::icosphere(Vec3::Zero(), 1.0, 2);
  cloud.faces.clear();  // a cloud: the distance is to the nearest point, easy to check
  cloud.normals.clear();
  const MedialMesh medial = random_medial(3);
  EvalOptions options;
  options.boundary_spacing = 0.01;
  const EvalResult result = evaluate(cloud, medial, options);
  const double spacing = options.boundary_spacing * result.diagonal;
  ASSERT_EQ(result.boundary_samples.size(), result.boundary_sample_count);
  ASSERT_EQ(result.boundary_samples,
            envelope_samples(medial, spacing, options.inside_tolerance * result.diagonal));
  ASSERT_EQ(result.boundary_error.size(), result.boundary_sample_count);
  double max = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < result.boundary_samples.size(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& p : cloud.points)
      nearest = std::min(nearest, (p - result.boundary_samples[i]).norm());
    ASSERT_NEAR(result.boundary_error[i], nearest, 1e-12) << "sample " << i;
    max = std::max(max, nearest);
    sum += nearest;
  }
  EXPECT_NEAR(result.medial_to_surface_mean, sum / result.boundary_sample_count, 1e-12);
  EXPECT_GE(result.medial_to_surface_max, max);
  EXPECT_LE(result.medial_to_surface_max, max + spacing);

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "vmas_eval_medial_errors";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_surface((dir / "cloud.off").string(), cloud);  // exact round trips
  write_medial_mesh((dir / "medial.ma").string(), medial);
  const std::string command = std::string(VMAS_CLI) + " eval " + (dir / "cloud.off").string() +
                              " " + (dir / "medial.ma").string() + " --medial-errors " +
                              (dir / "errors.txt").string() + " --spacing 0.01 > " +
                              (dir / "out").string();
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(dir / "errors.txt");
  std::string line, summary;
  std::size_t row = 0;
  while (std::getline(in, line)) {
    if (line.rfind('#', 0) == 0) {
      summary += line;
      continue;
    }
    ASSERT_LT(row, result.boundary_sample_count);
    std::istringstream values(line);
    double x, y, z, distance;
    ASSERT_TRUE(values >> x >> y >> z >> distance) << line;
    const Vec3& q = result.boundary_samples[row];
    EXPECT_NEAR((Vec3(x, y, z) - q).norm(), 0.0, 1e-8) << line;
    EXPECT_NEAR(distance, result.boundary_error[row], 1e-8) << line;
    ++row;
  }
  EXPECT_EQ(row, result.boundary_sample_count);
  std::ostringstream expected;
  expected << "medial_to_surface_max " << std::setprecision(6) << result.medial_to_surface_max;
  EXPECT_NE(summary.find(expected.str()), std::string::npos) << summary;
  std::filesystem::remove_all(dir);
}

TEST(Eval, DeterministicAcrossThreadCounts) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  const MedialMesh medial = random_medial(9);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const EvalResult one = evaluate(mesh, medial);
  omp_set_num_threads(2);
  const EvalResult two = evaluate(mesh, medial);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.hausdorff, two.hausdorff);
  EXPECT_EQ(one.surface_to_medial_mean, two.surface_to_medial_mean);
  EXPECT_EQ(one.medial_to_surface_mean, two.medial_to_surface_mean);
  EXPECT_EQ(one.vertex_error, two.vertex_error);
  EvalOptions options;
  options.seed = 2;
  EXPECT_NE(evaluate(mesh, medial, options).surface_to_medial_mean, one.surface_to_medial_mean);
}

// The evaluator reuses what it measured of primitives it saw before: a sequence of related
// reconstructions must measure exactly as fresh evaluations do.
TEST(Eval, AnEvaluatorMeasuringOneChangeAfterAnotherMatchesFreshEvaluations) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  std::vector<MedialMesh> sequence{random_medial(5)};
  MedialMesh changed = sequence.back();
  changed.spheres[3].radius *= 1.2;  // every primitive of sphere 3 changes
  sequence.push_back(changed);
  changed.spheres.push_back({Vec3(0.2, 0.1, -0.3), 0.3});  // a new sphere, an edge to it
  changed.edges.push_back({0, static_cast<int>(changed.spheres.size()) - 1});
  sequence.push_back(changed);
  changed.faces.pop_back();  // a slab goes
  sequence.push_back(changed);
  sequence.push_back(random_medial(5));  // back to the first
  for (bool maxima_only : {false, true}) {
    EvalOptions options;
    options.boundary_spacing = 0.01;
    options.maxima_only = maxima_only;
    Evaluator evaluator(mesh, options);
    for (std::size_t k = 0; k < sequence.size(); ++k) {
      const EvalResult reused = evaluator(sequence[k]);
      const EvalResult fresh = evaluate(mesh, sequence[k], options);
      EXPECT_EQ(reused.hausdorff, fresh.hausdorff) << k;
      EXPECT_EQ(reused.surface_to_medial_max, fresh.surface_to_medial_max) << k;
      EXPECT_EQ(reused.medial_to_surface_max, fresh.medial_to_surface_max) << k;
      EXPECT_EQ(reused.surface_to_medial_worst, fresh.surface_to_medial_worst) << k;
      EXPECT_EQ(reused.medial_to_surface_worst, fresh.medial_to_surface_worst) << k;
      EXPECT_EQ(reused.surface_to_medial_mean, fresh.surface_to_medial_mean) << k;
      EXPECT_EQ(reused.medial_to_surface_mean, fresh.medial_to_surface_mean) << k;
      EXPECT_EQ(reused.boundary_sample_count, fresh.boundary_sample_count) << k;
      EXPECT_EQ(reused.vertex_error, fresh.vertex_error) << k;
    }
  }
  // Maxima alone are those of the full evaluation, where they are too.
  EvalOptions only;
  only.maxima_only = true;
  const EvalResult full = evaluate(mesh, sequence[2]);
  const EvalResult maxima = evaluate(mesh, sequence[2], only);
  EXPECT_EQ(maxima.hausdorff, full.hausdorff);
  EXPECT_EQ(maxima.surface_to_medial_worst, full.surface_to_medial_worst);
  EXPECT_EQ(maxima.medial_to_surface_worst, full.medial_to_surface_worst);
  EXPECT_TRUE(maxima.vertex_error.empty());
  // The worst surface point is as far from the reconstruction as the maximum says.
  const double at_worst = envelope_distances(sequence[2], {full.surface_to_medial_worst}).front();
  EXPECT_DOUBLE_EQ(at_worst, full.surface_to_medial_max);
}

// With maxima_only, the evaluator searches exactly only the distances near the last maxima, and
// measures again when the maxima drop below that; returning to a kept state re-uses its
// measurements. Neither changes a figure.
TEST(Eval, MaximaAreExactWhateverWasMeasuredBeforeOrKept) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  MedialMesh exact;  // the sphere's own medial sphere: a tiny error after large ones
  exact.spheres.push_back({Vec3::Zero(), 0.999});
  MedialMesh shifted = random_medial(5);
  shifted.spheres[0].center.x() += 0.05;
  const std::vector<MedialMesh> sequence{random_medial(5), exact, random_medial(5), shifted,
                                         random_medial(5), exact};
  // ... and with weights (a density's: from 0.1 on one side to 1 on the other).
  for (const bool weighted : {false, true}) {
    EvalOptions options;
    options.boundary_spacing = 0.01;
    options.maxima_only = true;
    if (weighted) {
      options.surface_samples = 0;
      for (const Vec3& p : mesh.points)
        options.point_weights.push_back(std::min(1.0, 0.1 + 0.45 * (p.x() + 1.0)));
    }
    EvalOptions everything = options;
    everything.maxima_only = false;
    Evaluator evaluator(mesh, options);
    for (std::size_t k = 0; k < sequence.size(); ++k) {
      if (k == 1) evaluator.keep_memory();  // the state after sequence[0]
      if (k == 4) evaluator.restore_memory();
      const EvalResult measured = evaluator(sequence[k]);
      const EvalResult all = evaluate(mesh, sequence[k], everything);
      EXPECT_EQ(measured.surface_to_medial_max, all.surface_to_medial_max) << k << weighted;
      EXPECT_EQ(measured.medial_to_surface_max, all.medial_to_surface_max) << k << weighted;
      EXPECT_EQ(measured.surface_to_medial_worst, all.surface_to_medial_worst) << k << weighted;
      EXPECT_EQ(measured.medial_to_surface_worst, all.medial_to_surface_worst) << k << weighted;
    }
  }
}

// Coincident spheres give identical primitives: measured once, but counted as fresh evaluation
// counts them.
TEST(Eval, AnEvaluatorHandlesCoincidentSpheresAsFreshEvaluationsDo) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  MedialMesh medial = random_medial(7);
  medial.spheres.push_back(medial.spheres[2]);  // sphere 2 twice, with its own edge
  medial.edges.push_back({static_cast<int>(medial.spheres.size()) - 1, 4});
  EvalOptions options;
  options.boundary_spacing = 0.01;
  Evaluator evaluator(mesh, options);
  for (const MedialMesh& m : {random_medial(7), medial, medial}) {
    const EvalResult reused = evaluator(m);
    const EvalResult fresh = evaluate(mesh, m, options);
    EXPECT_EQ(reused.hausdorff, fresh.hausdorff);
    EXPECT_EQ(reused.medial_to_surface_mean, fresh.medial_to_surface_mean);
    EXPECT_EQ(reused.surface_to_medial_mean, fresh.surface_to_medial_mean);
    EXPECT_EQ(reused.boundary_sample_count, fresh.boundary_sample_count);
  }
}

TEST(Eval, BadInputsThrow) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 1);
  MedialMesh medial;
  EXPECT_THROW(evaluate(mesh, medial), InvalidInput);  // no sphere
  medial.spheres = {{Vec3::Zero(), 0.5}, {Vec3(0.5, 0, 0), 0.2}};
  EXPECT_NO_THROW(evaluate(mesh, medial));

  MedialMesh bad = medial;
  bad.edges = {{0, 2}};
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);
  bad.edges = {{1, 1}};
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);
  bad = medial;
  bad.faces = {{0, 1, -1}};
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);
  EXPECT_THROW(envelope_samples(bad, 0.01, 0.0), InvalidInput);
  bad = medial;
  bad.spheres[1].radius = std::nan("");
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);
  bad.spheres[1].radius = -0.1;
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);
  bad = medial;
  bad.spheres[0].center.x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(evaluate(mesh, bad), InvalidInput);

  EXPECT_THROW(evaluate(SurfaceInput{}, medial), InvalidInput);
  SurfaceInput broken = mesh;
  broken.faces.push_back({0, 1, static_cast<int>(mesh.points.size())});
  EXPECT_THROW(evaluate(broken, medial), InvalidInput);

  EvalOptions options;
  options.surface_samples = -2;
  EXPECT_THROW(options.validate(), InvalidOption);
  EXPECT_THROW(evaluate(mesh, medial, options), InvalidOption);
  options = {};
  options.boundary_spacing = 0.0;
  EXPECT_THROW(options.validate(), InvalidOption);
  options = {};
  options.inside_tolerance = -1.0;
  EXPECT_THROW(options.validate(), InvalidOption);
  options = {};
  options.max_input_points = 100;  // vertex_error would miss points
  EXPECT_THROW(options.validate(), InvalidOption);
  options.maxima_only = true;
  EXPECT_NO_THROW(options.validate());
}

// The paper's Table 1 on the reference medial meshes (ε in % of the diagonal).
TEST(EvalReference, ReproducesPaperTable1) {
  REQUIRE_SHARED_DATA("reference");
  const std::string data = test::shared_data();
  struct Case {
    const char* model;
    const char* method;
    double paper;
  };
  for (const Case& c :
       {Case{"armadillo", "qmat", 3.860}, Case{"armadillo", "coverage_axis_pp", 3.905},
        Case{"pinion", "qmat", 2.194}, Case{"vessel", "coverage_axis", 3.054}}) {
    const SurfaceInput mesh = read_surface(data + "/meshes/" + c.model + ".off");
    const MedialMesh medial =
        read_medial_mesh(data + "/reference/" + c.model + "/" + c.method + ".ma");
    const EvalResult result = evaluate(mesh, medial);
    EXPECT_NEAR(result.percent(result.hausdorff), c.paper, 0.4) << c.model << " " << c.method;
  }
}

// A medial mesh far larger than the shape (a hostile or broken .ma) is measured in bounded
// work: at the default spacing this sphere alone would take ~10^8 boundary samples.
TEST(EvalBounds, OutsizedPrimitivesAreSampledCoarser) {
  const SurfaceInput shape = test::icosphere(Vec3::Zero(), 1.0, 2);
  MedialMesh huge;
  huge.spheres = {{Vec3::Zero(), 50.0}, {Vec3(60.0, 0.0, 0.0), 40.0}};
  huge.edges = {{0, 1}};
  const EvalResult result = evaluate(shape, huge);
  EXPECT_LE(result.boundary_sample_count, 500000u);
  EXPECT_GT(result.boundary_sample_count, 1000u);
  EXPECT_TRUE(std::isfinite(result.hausdorff));
  EXPECT_GT(result.hausdorff, 40.0);  // the far side of the big sphere
}

// Degenerate medial meshes are measured as what they are: a sphere of radius 0 is its centre (no
// NaN from a tangent plane it does not have), a face given many times is that face.
TEST(EvalBounds, PointSpheresAndRepeatedFacesAreMeasuredAsWhatTheyAre) {
  const SurfaceInput shape = test::icosphere(Vec3::Zero(), 1.0, 2);
  MedialMesh point;
  point.spheres = {{Vec3(0.5, 0.0, 0.0), 0.0}};
  const EvalResult at_point = evaluate(shape, point);
  EXPECT_TRUE(std::isfinite(at_point.medial_to_surface_max));
  EXPECT_NEAR(at_point.medial_to_surface_max, 0.5, 0.02);  // the centre is 0.5 from the surface
  EXPECT_NEAR(at_point.hausdorff, 1.5, 0.02);              // the far side of the ball

  MedialMesh once;
  once.spheres = {
      {Vec3(-0.3, -0.2, 0.0), 0.4}, {Vec3(0.3, -0.2, 0.0), 0.4}, {Vec3(0.0, 0.3, 0.0), 0.4}};
  once.faces = {{0, 1, 2}};
  MedialMesh repeated = once;
  for (int i = 0; i < 300; ++i)
    repeated.faces.push_back(i % 2 ? std::array<int, 3>{2, 0, 1} : once.faces[0]);
  const EvalResult a = evaluate(shape, once), b = evaluate(shape, repeated);
  EXPECT_EQ(a.hausdorff, b.hausdorff);
  EXPECT_EQ(a.boundary_sample_count, b.boundary_sample_count);
  EXPECT_EQ(a.medial_to_surface_mean, b.medial_to_surface_mean);
}

// A ball's cloud with its top cut off (z > 0.5): one opening, whose rim plane is z = 0.5. The
// unit ball reaches 0.5 past it over the opening; a ball of radius 0.5 reaches it, no farther;
// the whole ball's cloud has no opening.
TEST(Openings, ReachPastTheRimPlaneOfACutBall) {
  const test::Sample ball = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 5);
  SurfaceInput cut;
  for (std::size_t i = 0; i < ball.points.size(); ++i)
    if (ball.points[i].z() <= 0.5) {
      cut.points.push_back(ball.points[i]);
      cut.normals.push_back(ball.normals[i]);
    }
  MedialMesh unit, half;
  unit.spheres = {{Vec3::Zero(), 1.0}};
  half.spheres = {{Vec3::Zero(), 0.5}};
  const EvalResult unit_fit = evaluate(cut, unit);
  const OpeningReach unit_reach = opening_reach(cut, unit_fit);
  EXPECT_EQ(unit_reach.openings, 1);
  const double spacing = EvalOptions{}.boundary_spacing * unit_fit.diagonal;
  EXPECT_NEAR(unit_reach.reach, 0.5, spacing);
  const OpeningReach half_reach = opening_reach(cut, evaluate(cut, half));
  EXPECT_EQ(half_reach.openings, 1);
  EXPECT_LT(half_reach.reach, spacing);
  // Whole, or as a mesh: nothing to reach past.
  SurfaceInput whole;
  whole.points = ball.points;
  whole.normals = ball.normals;
  EXPECT_EQ(opening_reach(whole, evaluate(whole, unit)).openings, 0);
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 3);
  const OpeningReach of_mesh = opening_reach(mesh, evaluate(mesh, unit));
  EXPECT_EQ(of_mesh.openings, 0);
  EXPECT_EQ(of_mesh.reach, 0.0);
}

// Lid points close an opening for the medial -> surface side only: a point above the opening's
// centre is as far as the lid, not as the rim; the surface side still measures from the cloud.
TEST(Evaluator, LidPointsCountOnlyForTheMedialSide) {
  SurfaceInput cloud;
  for (int i = 0; i < 400; ++i) {
    const double angle = 2.0 * M_PI * i / 400.0;
    for (double z : {0.0, 0.1, 0.2}) cloud.points.push_back(Vec3(std::cos(angle), std::sin(angle), z));
  }
  EvalOptions options;
  Evaluator open(cloud, options);
  options.lid_points = {Vec3(0.0, 0.0, 0.2)};
  Evaluator closed(cloud, options);
  const std::vector<Vec3> above = {Vec3(0.0, 0.0, 0.3)};
  EXPECT_NEAR(open.distances_to_shape(above).front(), std::hypot(1.0, 0.1), 1e-9);
  EXPECT_NEAR(closed.distances_to_shape(above).front(), 0.1, 1e-9);
  // A sphere filling the ring and bulging above it: the surface side is the same with the lid,
  // the medial side nearer.
  MedialMesh medial;
  medial.spheres.push_back({Vec3(0.0, 0.0, 0.1), 1.0});
  const EvalResult without = open(medial), with = closed(medial);
  EXPECT_EQ(with.surface_sample_count, without.surface_sample_count);
  EXPECT_DOUBLE_EQ(with.surface_to_medial_max, without.surface_to_medial_max);
  EXPECT_LT(with.medial_to_surface_max, without.medial_to_surface_max);
}

// A sphere shifted along x from a unit sphere's medial sphere is 0.1 off at both poles, on both
// sides; weights make the pole where they are high the worst.
TEST(Evaluator, PointWeightsScaleTheDistancesOfBothSides) {
  const SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  MedialMesh medial;
  medial.spheres = {{Vec3(0.1, 0, 0), 1.0}};
  EvalOptions options;
  options.surface_samples = 0;
  for (const double light_side : {1.0, -1.0}) {
    options.point_weights.clear();
    for (const Vec3& p : mesh.points)
      options.point_weights.push_back(p.x() * light_side > 0 ? 0.25 : 1.0);
    const EvalResult result = Evaluator(mesh, options)(medial);
    EXPECT_NEAR(result.surface_to_medial_max, 0.1, 3e-3);
    EXPECT_NEAR(result.medial_to_surface_max, 0.1, 3e-3);
    EXPECT_LT(result.surface_to_medial_worst.x() * light_side, -0.9);
    EXPECT_LT(result.medial_to_surface_worst.x() * light_side, -0.8);
  }
  options.point_weights.assign(mesh.points.size(), 0.5);
  const EvalResult half = Evaluator(mesh, options)(medial);
  EXPECT_NEAR(half.hausdorff, 0.05, 2e-3);
  // Refused: a weight beyond [0, 1], one per point missing, random samples (no weight).
  options.point_weights[3] = 1.5;
  EXPECT_THROW(Evaluator(mesh, options), InvalidOption);
  options.point_weights.assign(mesh.points.size() - 1, 1.0);
  EXPECT_THROW(Evaluator(mesh, options), InvalidOption);
  options.point_weights.assign(mesh.points.size(), 1.0);
  options.surface_samples = -1;
  EXPECT_THROW(Evaluator(mesh, options), InvalidOption);
}

}  // namespace
}  // namespace vmas
