#include <gtest/gtest.h>

#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

SkeletonizerOptions with_target(int spheres) {
  SkeletonizerOptions options;
  options.target_spheres = spheres;
  return options;
}

TEST(Skeletonizer, SphereGivesOneSphereAtItsCentre) {
  const Vec3 center(0.3, -0.2, 0.5);
  Skeletonizer skeletonizer(build_shape(test::icosphere(center, 2.0, 4), {}), with_target(1));
  const RunSummary summary = skeletonizer.run();
  EXPECT_TRUE(summary.converged);
  ASSERT_EQ(skeletonizer.spheres().size(), 1u);
  EXPECT_LT((skeletonizer.spheres()[0].center - center).norm(), 0.02);
  EXPECT_NEAR(skeletonizer.spheres()[0].radius, 2.0, 0.02);
}

}  // namespace
}  // namespace vmas
