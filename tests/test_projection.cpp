// Tests of the projection stage (src/optimise/projection.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "optimise/projection.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Projection, ShrinkingBallIsEmptyAndTouchesItsPoint) {
  const Shape shape = build_shape(test::torus(1.0, 0.3, 64, 24), {});
  ShrinkingBallOptions exact;
  exact.denoise_angle_deg = 0.0;  // denoising may stop early, leaving a slightly overlapping ball
  for (const ShrinkingBallOptions& options : {exact, ShrinkingBallOptions{}}) {
    const MedialProjector projector(shape, options);
    const double tolerance = options.denoise_angle_deg > 0.0 ? 0.002 : 1e-5 * shape.diagonal;
    for (int v = 0; v < shape.size(); v += 37) {
      const Sphere ball = projector.shrink(v, -shape.normals[v]);
      EXPECT_NEAR((shape.points[v] - ball.center).norm(), ball.radius, 1e-9);
      for (const Vec3& p : shape.points)
        EXPECT_GE((p - ball.center).norm(), ball.radius - tolerance);
      // On a torus the medial axis is the centre circle: radius ≈ tube radius.
      EXPECT_NEAR(ball.radius, 0.3, 0.01);
    }
  }
}

TEST(Projection, ProjectLandsOnTheMedialAxis) {
  const Shape shape = build_shape(test::icosphere(Vec3::Zero(), 1.0, 4), {});
  const MedialProjector projector(shape, {});
  // A fitted centre near the medial axis (here: the centre) is pulled onto it.
  const Sphere projected = projector.project(Vec3(0.1, 0.05, -0.05));
  EXPECT_LT(projected.center.norm(), 0.05);
  EXPECT_NEAR(projected.radius, 1.0, 0.05);
}

SurfaceInput cloud_of(const test::Sample& sample) {
  SurfaceInput cloud;
  cloud.points = sample.points;
  cloud.normals = sample.normals;
  return cloud;
}

// The same shape with the faces' rules for inside and outside (a mesh has no exterior grid).
Shape without_exterior_grid(Shape shape) {
  shape.is_mesh = true;
  return shape;
}

TEST(Projection, ACloudsBallsStayInsideWhereItsNormalsAreFlipped) {
  // Two sampled unit spheres a unit apart, the second with its normals pointing inward (as
  // estimation leaves whole patches across thin parts). From the second sphere's points facing
  // the first, the ball along −normal stops on the first sphere: a ball in the gap that the
  // contact's normal accepts. The exterior grid rejects it.
  const test::Sample a = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 41);
  const test::Sample b = test::sample_sphere(Vec3(3.0, 0.0, 0.0), 1.0, 20000, 42);
  SurfaceInput cloud = cloud_of(a);
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    cloud.points.push_back(b.points[i]);
    cloud.normals.push_back(-b.normals[i]);
  }
  const Shape shape = build_shape(cloud, {});
  const Shape unguarded = without_exterior_grid(shape);
  const MedialProjector projector(shape, {}), unguarded_projector(unguarded, {});
  const auto in_a_sphere = [](const Sphere& ball) {
    return std::min(ball.center.norm(), (ball.center - Vec3(3.0, 0.0, 0.0)).norm()) <= 1.01;
  };
  int facing = 0, outside_unguarded = 0;
  for (int v = 0; v < shape.size(); ++v) {
    if (shape.points[v].x() > 2.2) continue;  // the second sphere's side facing the first
    if (shape.points[v].x() < 1.8) continue;
    ++facing;
    EXPECT_TRUE(in_a_sphere(projector.ball_at(v))) << "vertex " << v;
    if (!in_a_sphere(unguarded_projector.ball_at(v))) ++outside_unguarded;
  }
  EXPECT_GT(facing, 300);
  EXPECT_GT(outside_unguarded, facing / 2);  // what the grid prevents
}

TEST(Projection, AThinPlateSampledAsACloudKeepsItsBallsInside) {
  // A plate thinner than its samples' spacing: balls pass between the samples of the far side.
  // Its samples wall it solid, so the grid keeps every ball's centre in the plate.
  const test::Sample plate = test::sample_box(Vec3(1.0, 1.0, 0.01), 20000, 43);
  const Shape shape = build_shape(cloud_of(plate), {});
  const Shape unguarded_shape = without_exterior_grid(shape);  // the projectors keep a reference
  const MedialProjector projector(shape, {}), unguarded(unguarded_shape, {});
  const auto in_plate = [](const Sphere& ball) {
    return ball.center.z() >= -1e-4 && ball.center.z() <= 0.01 + 1e-4;
  };
  int measured = 0, outside_unguarded = 0;
  for (int v = 0; v < shape.size(); ++v) {
    const Vec3& p = shape.points[v];
    if (std::abs(shape.normals[v].z()) < 0.9 || std::min(p.x(), p.y()) < 0.1 ||
        std::max(p.x(), p.y()) > 0.9)
      continue;
    ++measured;
    EXPECT_TRUE(in_plate(projector.ball_at(v))) << "vertex " << v;
    if (!in_plate(unguarded.ball_at(v))) ++outside_unguarded;
  }
  EXPECT_GT(measured, 1000);
  EXPECT_GT(outside_unguarded, 0);  // what the grid prevents
}

TEST(Projection, AnOpenCloudHasNoExteriorGrid) {
  // A hemisphere: the fill reaches its inside through the open side, so the grid is dropped and
  // the balls are those of the normals alone.
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 47);
  SurfaceInput open;
  for (std::size_t i = 0; i < sphere.points.size(); ++i)
    if (sphere.points[i].z() > 0.0) {
      open.points.push_back(sphere.points[i]);
      open.normals.push_back(sphere.normals[i]);
    }
  const Shape shape = build_shape(open, {});
  const Shape unguarded_shape = without_exterior_grid(shape);  // the projectors keep a reference
  const MedialProjector projector(shape, {}), unguarded(unguarded_shape, {});
  for (int v = 0; v < shape.size(); v += 11) {
    const Sphere ball = projector.ball_at(v);
    EXPECT_EQ(ball.center, unguarded.ball_at(v).center) << "vertex " << v;
    EXPECT_EQ(ball.radius, unguarded.ball_at(v).radius) << "vertex " << v;
  }
}

// An enclosure measured elsewhere (on a denser sampling of the same surface) is taken as it is;
// a figure that is not one is refused.
TEST(Projection, AGivenEnclosureIsTakenAndChecked) {
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 48);
  SurfaceInput cloud;
  cloud.points = sphere.points;
  cloud.normals = sphere.normals;
  const Shape shape = build_shape(cloud, {});
  EXPECT_NEAR(MedialProjector(shape, {}).enclosure(), 1.0, 0.1);
  ShrinkingBallOptions given;
  given.enclosure = 0.25;
  EXPECT_EQ(MedialProjector(shape, given).enclosure(), 0.25);
  given.enclosure = std::nan("");
  EXPECT_THROW(given.validate(), InvalidOption);
}

// Measured alone, the enclosure is what a whole projector measures; an open cap reads lower.
TEST(Projection, TheEnclosureMeasuredAloneIsAProjectorsEnclosure) {
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 49);
  SurfaceInput cloud;
  for (std::size_t i = 0; i < sphere.points.size(); ++i)
    if (sphere.points[i].z() < 0.2) {
      cloud.points.push_back(sphere.points[i]);
      cloud.normals.push_back(sphere.normals[i]);
    }
  const Shape open = build_shape(cloud, {});
  EXPECT_EQ(MedialProjector::enclosure_of(open, {}), MedialProjector(open, {}).enclosure());
  EXPECT_LT(MedialProjector::enclosure_of(open, {}), 0.8);
  cloud.points = sphere.points;
  cloud.normals = sphere.normals;
  const Shape closed = build_shape(cloud, {});
  EXPECT_EQ(MedialProjector::enclosure_of(closed, {}), MedialProjector(closed, {}).enclosure());
}

// A small patch of a torus's normals turned over (as orientation leaves one near a thin part)
// reads inside out; the rest of the torus, and a thin plate oriented right, do not. (A patch
// wider than the offset reads right: its own samples outweigh the rest.)
TEST(Projection, ASmallPatchTurnedInsideOutIsFoundAndNothingElse) {
  const test::Sample torus = test::sample_torus(1.0, 0.3, 4000, 51);
  SurfaceInput cloud = cloud_of(torus);
  const Vec3 middle(1.3, 0.0, 0.0);  // on the outer equator
  std::vector<char> in_patch(cloud.points.size(), 0);
  int patch = 0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if ((cloud.points[i] - middle).norm() < 0.12) {  // the offset is about 0.2
      in_patch[i] = 1;
      cloud.normals[i] = -cloud.normals[i];
      ++patch;
    }
  EXPECT_TRUE(MedialProjector::inside_out(build_shape(cloud_of(torus), {})).empty());
  const std::vector<int> turned = MedialProjector::inside_out(build_shape(cloud, {}));
  int found = 0;
  for (int v : turned) {
    EXPECT_TRUE(in_patch[v]) << "vertex " << v << " at " << cloud.points[v].transpose();
    found += in_patch[v];
  }
  EXPECT_GT(patch, 10);
  EXPECT_EQ(found, patch);
  const test::Sample plate = test::sample_box(Vec3(1.0, 1.0, 0.01), 20000, 52);
  const Shape plate_shape = build_shape(cloud_of(plate), {});
  ASSERT_GE(MedialProjector::enclosure_of(plate_shape, {}), MedialProjector::kEnclosed);
  EXPECT_TRUE(MedialProjector::inside_out(plate_shape).empty());
}

// On an open surface the rest reads no 1 inside: nothing is judged there, not even a small
// patch turned over.
TEST(Projection, NothingIsTurnedOnAnOpenSurface) {
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 8000, 54);
  SurfaceInput open;
  int patch = 0;
  for (std::size_t i = 0; i < sphere.points.size(); ++i) {
    if (sphere.points[i].z() < 0.0) continue;
    open.points.push_back(sphere.points[i]);
    const bool turned = (sphere.points[i] - Vec3(1.0, 0.0, 0.3).normalized()).norm() < 0.1;
    open.normals.push_back(turned ? Vec3(-sphere.normals[i]) : sphere.normals[i]);
    patch += turned;
  }
  ASSERT_GT(patch, 5);
  const Shape shape = build_shape(open, {});
  ASSERT_LT(MedialProjector::enclosure_of(shape, {}), MedialProjector::kEnclosed);
  EXPECT_TRUE(MedialProjector::inside_out(shape).empty());
}

}  // namespace
}  // namespace vmas
