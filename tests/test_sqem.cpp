// Tests of the sqem stage (src/sqem.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_shapes.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/types.hpp"

namespace vmas {
namespace {

TEST(Sqem, MatchesSquaredPlaneDistanceAndIsZeroOnTangentSphere) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 50; ++trial) {
    const auto draw = [&] { return gauss(rng); };
    const Vec3 point = test::draw_xyz(draw);
    const Vec3 normal = test::draw_xyz(draw).normalized();
    const Sphere sphere{test::draw_xyz(draw), std::abs(gauss(rng))};
    const double plane_distance = normal.dot(point - sphere.center) - sphere.radius;
    EXPECT_NEAR(Sqem::plane(point, normal)(sphere), plane_distance * plane_distance, 1e-9);
    // A sphere tangent to the plane from the inside has zero error.
    const Sphere tangent{point - 0.7 * normal, 0.7};
    EXPECT_NEAR(Sqem::plane(point, normal)(tangent), 0.0, 1e-12);
  }
}

TEST(Sqem, SumOfSphereVertexQuadricsIsZeroOnTheExactSphere) {
  const Vec3 center(1, 2, 3);
  const Shape shape = build_shape(test::icosphere(center, 0.5, 3), {});
  Sqem total;
  for (const auto& q : shape.quadric) total += q;
  // Vertex normals of the mesh are face normals, so the fit is exact only up to faceting.
  EXPECT_LT(total(Sphere{center, 0.5}) / shape.total_area, 1e-4 * 0.25);
  EXPECT_GT(total(Sphere{center, 0.45}) / shape.total_area,
            10 * total(Sphere{center, 0.5}) / shape.total_area);
}

}  // namespace
}  // namespace vmas
