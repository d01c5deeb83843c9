// Spheres that are no medial balls of a closed input are counted: a centre outside the solid, a
// radius that is not the distance to the surface.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace vmas
