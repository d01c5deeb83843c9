// Spheres that are no medial balls of a closed input are counted: a centre outside the solid, a
// radius that is not the distance to the surface.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "pipeline/validity.hpp"
#include "refine/refine.hpp"
#include "test_shapes.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Validity, CentresOutsideAndRadiiOffTheSurfaceAreCounted) {
  const SurfaceInput ball = test::icosphere(Vec3::Zero(), 1.0, 4);
  const Shape shape = build_shape(ball, {});
  const MedialProjector projector(shape, {});
  const Evaluator evaluator(ball, refinement_eval_options());
  const double diagonal = shape.diagonal;
  // The medial ball, and spheres near it that are medial within the tolerance.
  const std::vector<Sphere> medial = {{Vec3::Zero(), 1.0}, {Vec3(0.2, 0.0, 0.0), 0.8}};
  const InvalidSpheres none = invalid_spheres(medial, projector, evaluator, diagonal);
  EXPECT_TRUE(none.checked);
  EXPECT_EQ(none.outside, 0u);
  EXPECT_EQ(none.radius_off, 0u);
  // Inside but too small; outside with the right distance; outside and too big.
  const std::vector<Sphere> wrong = {
      {Vec3::Zero(), 0.5}, {Vec3(2.0, 0.0, 0.0), 1.0}, {Vec3(0.0, 1.5, 0.0), 1.0}};
  const InvalidSpheres counted = invalid_spheres(wrong, projector, evaluator, diagonal);
  EXPECT_EQ(counted.outside, 2u);
  EXPECT_EQ(counted.radius_off, 2u);
}

// A missing loop is opened only where a tunnel fits: a triangle of three spheres around a torus's
// hole (its centroid in the hole) may go, one spanning the solid of a ball may not.
TEST(Validity, TunnelsFitWhereTheSolidIsOpenOrShallow) {
  const SurfaceInput torus = test::torus(1.0, 0.3, 48, 24);
  const Shape shape = build_shape(torus, {});
  const MedialProjector projector(shape, {});
  const Evaluator evaluator(torus, refinement_eval_options());
  std::vector<Sphere> spheres;
  for (int i = 0; i < 3; ++i) {
    const double angle = 2.0 * 3.14159265358979 * i / 3.0;
    spheres.push_back({Vec3(std::cos(angle), std::sin(angle), 0.0), 0.3});
  }
  // Three spheres inside the tube, close together: their centroid lies about 0.27 deep in the solid.
  spheres.push_back({Vec3(1.0, -0.05, 0.0), 0.25});
  spheres.push_back({Vec3(1.0, 0.05, 0.0), 0.25});
  spheres.push_back({Vec3(0.95, 0.0, 0.05), 0.25});
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  const auto fitting = where_tunnels_fit(triangles, spheres, projector, evaluator, 0.05);
  ASSERT_EQ(fitting.size(), 1u);
  EXPECT_EQ(fitting.front(), (std::array<int, 3>{0, 1, 2}));
  // As deep as the error allows, both.
  EXPECT_EQ(where_tunnels_fit(triangles, spheres, projector, evaluator, 0.3).size(), 2u);
}

}  // namespace
}  // namespace vmas
