#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

SkeletonizerOptions with_target(int spheres) {
  SkeletonizerOptions options;
  options.target.spheres = spheres;
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

TEST(Skeletonizer, CapsuleCentresLieOnTheAxisWithTheTubeRadius) {
  const double radius = 0.25, length = 2.0;
  Skeletonizer skeletonizer(build_shape(test::capsule(radius, length, 10, 32), {}), with_target(8));
  skeletonizer.run();
  ASSERT_EQ(skeletonizer.spheres().size(), 8u);
  for (const Sphere& s : skeletonizer.spheres()) {
    EXPECT_LT(s.center.head<2>().norm(), 0.02 * length) << s.center.transpose();
    EXPECT_NEAR(s.radius, radius, 0.02);
    EXPECT_GT(s.center.z(), -0.01);
    EXPECT_LT(s.center.z(), length + 0.01);
  }
  const MedialMesh mesh = skeletonizer.medial_mesh();
  EXPECT_GE(mesh.edges.size(), 7u);  // a chain at least
}

TEST(Skeletonizer, TorusGivesAClosedLoop) {
  Skeletonizer skeletonizer(build_shape(test::torus(1.0, 0.25, 96, 24), {}), with_target(12));
  skeletonizer.run();
  const MedialMesh mesh = skeletonizer.medial_mesh();
  ASSERT_EQ(mesh.spheres.size(), 12u);
  for (const Sphere& s : mesh.spheres) {
    EXPECT_NEAR(s.center.head<2>().norm(), 1.0, 0.03);
    EXPECT_NEAR(s.center.z(), 0.0, 0.03);
  }
  // A loop: every sphere has two neighbours along the ring, and the graph has a cycle.
  std::vector<int> degree(mesh.spheres.size(), 0);
  for (const auto& e : mesh.edges) {
    ++degree[e[0]];
    ++degree[e[1]];
  }
  for (int d : degree) EXPECT_GE(d, 2);
  EXPECT_GE(mesh.edges.size(), mesh.spheres.size());
}

TEST(Skeletonizer, SphereCountIsMetExactly) {
  for (int target : {1, 7, 20}) {
    Skeletonizer skeletonizer(build_shape(test::capsule(0.2, 1.5, 10, 32), {}),
                              with_target(target));
    skeletonizer.run();
    EXPECT_EQ(skeletonizer.spheres().size(), static_cast<std::size_t>(target));
  }
}

TEST(Skeletonizer, ErrorThresholdStopsSplitting) {
  SkeletonizerOptions options;
  options.target.error = 0.01;
  Skeletonizer coarse(build_shape(test::capsule(0.2, 1.5, 10, 32), {}), options);
  coarse.run();
  options.target.error = 0.002;
  Skeletonizer fine(build_shape(test::capsule(0.2, 1.5, 10, 32), {}), options);
  fine.run();
  EXPECT_LT(coarse.spheres().size(), fine.spheres().size());
  const double limit = std::pow(0.002 * fine.shape().diagonal, 2);
  for (double e : fine.cluster_errors()) EXPECT_LE(e, limit * 1.0001);
}

// A threshold finer than the data allows stops at one sphere per point, not at max_spheres
// (40 random points once gave 5000 spheres).
TEST(Skeletonizer, ErrorThresholdNeverGivesMoreSpheresThanPoints) {
  const test::Sample few = test::sample_sphere(Vec3::Zero(), 1.0, 40, 9);
  SurfaceInput cloud;
  cloud.points = test::with_noise(few.points, 0.2, 3);
  cloud.normals = few.normals;
  SkeletonizerOptions options;
  options.target.error = 1e-4;
  Skeletonizer skeletonizer(build_shape(cloud, {}), options);
  skeletonizer.run();
  EXPECT_LE(skeletonizer.spheres().size(), 40u);
  EXPECT_GE(skeletonizer.spheres().size(), 2u);
}

TEST(Skeletonizer, DynamicEditingBetweenSteps) {
  Skeletonizer skeletonizer(build_shape(test::capsule(0.2, 1.5, 10, 32), {}), with_target(5));
  skeletonizer.run();
  ASSERT_EQ(skeletonizer.spheres().size(), 5u);

  const int added = skeletonizer.add_sphere_at(0);
  EXPECT_EQ(added, 5);
  EXPECT_EQ(skeletonizer.spheres().size(), 6u);
  for (int label : skeletonizer.labels()) EXPECT_TRUE(label >= 0 && label < 6);
  skeletonizer.step();

  const Sphere kept = skeletonizer.spheres()[1];
  skeletonizer.freeze(1);
  skeletonizer.step();
  skeletonizer.step();
  EXPECT_EQ(skeletonizer.spheres()[1].center, kept.center);
  EXPECT_EQ(skeletonizer.spheres()[1].radius, kept.radius);

  const std::size_t before = skeletonizer.spheres().size();
  skeletonizer.remove_sphere(0);
  EXPECT_EQ(skeletonizer.spheres().size(), before - 1);
  EXPECT_TRUE(skeletonizer.frozen(0));  // the frozen sphere moved from id 1 to id 0
  for (int label : skeletonizer.labels())
    EXPECT_TRUE(label >= 0 && label < static_cast<int>(before - 1));
  skeletonizer.step();

  EXPECT_THROW(skeletonizer.remove_sphere(99), InvalidArgument);
  EXPECT_THROW(skeletonizer.add_sphere_at(-1), InvalidArgument);
}

// Passing over settled spheres (the same members, moved by rounding at most), steps leave a
// settled skeleton exactly as it is, until an edit, a new λ or a new density moves it.
TEST(Skeletonizer, SettledSpheresStayPutUntilSomethingChanges) {
  const test::Sample cloud = test::sample_torus(1.0, 0.3, 3000, 7);
  Skeletonizer skeletonizer(build_shape(cloud.cloud(), {}), with_target(12));
  skeletonizer.run();
  skeletonizer.pass_over_settled(true);
  for (int i = 0; i < 40; ++i) skeletonizer.step();
  const auto moved_since = [&](const std::vector<Sphere>& before) {
    int moved = 0;
    for (std::size_t c = 0; c < before.size(); ++c)
      moved += skeletonizer.spheres()[c].center != before[c].center ||
               skeletonizer.spheres()[c].radius != before[c].radius;
    return moved;
  };
  const std::vector<Sphere> settled = skeletonizer.spheres();
  for (int i = 0; i < 5; ++i) skeletonizer.step();
  EXPECT_EQ(moved_since(settled), 0);

  skeletonizer.set_lambda(skeletonizer.options().lambda * 4);
  skeletonizer.step();
  EXPECT_GT(moved_since(settled), 6);

  for (int i = 0; i < 40; ++i) skeletonizer.step();
  const std::vector<Sphere> settled_again = skeletonizer.spheres();
  std::vector<double> density(skeletonizer.shape().size(), 1.0);
  for (int v = 0; v < skeletonizer.shape().size(); ++v)
    if (skeletonizer.shape().points[v].x() > 0.5) density[v] = 4.0;
  skeletonizer.set_density(density);
  skeletonizer.step();
  EXPECT_GT(moved_since(settled_again), 0);

  for (int i = 0; i < 40; ++i) skeletonizer.step();
  skeletonizer.remove_sphere(0);
  const std::vector<Sphere> after_removal = skeletonizer.spheres();
  skeletonizer.step();
  EXPECT_GT(moved_since(after_removal), 0);
}

// A sphere keeps its key whatever is added or removed; a restored state brings its keys back.
TEST(Skeletonizer, KeysStayWithTheirSpheres) {
  Skeletonizer skeletonizer(build_shape(test::capsule(0.2, 1.5, 10, 32), {}), with_target(5));
  skeletonizer.run();
  const std::vector<std::uint64_t> keys = skeletonizer.keys();
  ASSERT_EQ(keys.size(), 5u);
  EXPECT_EQ(std::set<std::uint64_t>(keys.begin(), keys.end()).size(), 5u);
  const SkeletonizerState before = skeletonizer.state();
  const Sphere third = skeletonizer.spheres()[2];
  skeletonizer.remove_sphere(1);
  EXPECT_EQ(skeletonizer.id_of(keys[1]), -1);
  ASSERT_EQ(skeletonizer.id_of(keys[2]), 1);
  EXPECT_EQ(skeletonizer.spheres()[1].center, third.center);
  const int added = skeletonizer.add_sphere_at(0);
  const std::uint64_t new_key = skeletonizer.keys()[added];
  EXPECT_EQ(std::count(keys.begin(), keys.end(), new_key), 0);  // never one used before
  skeletonizer.step();
  EXPECT_EQ(skeletonizer.id_of(new_key), added);
  skeletonizer.restore(before);
  EXPECT_EQ(skeletonizer.keys(), keys);
  EXPECT_NE(skeletonizer.keys()[skeletonizer.add_sphere_at(3)], new_key);
}

TEST(Skeletonizer, BadOptionsAreRejected) {
  const Shape shape = build_shape(test::icosphere(Vec3::Zero(), 1.0, 2), {});
  SkeletonizerOptions options;
  options.target = {10, 0.01};  // a count and a threshold
  EXPECT_THROW(Skeletonizer(shape, options), InvalidOption);
  options.target = {-1, 0.0};
  EXPECT_THROW(Skeletonizer(shape, options), InvalidOption);
  options.target = {1, 0.0};
  options.lambda = -1;
  EXPECT_THROW(Skeletonizer(shape, options), InvalidOption);
  options.lambda = 0.2;
  options.target.spheres = shape.size() + 1;
  EXPECT_THROW(Skeletonizer(shape, options), InvalidOption);
}

TEST(Skeletonizer, SameOutputWithOneAndTwoThreads) {
  const Shape shape = build_shape(test::torus(1.0, 0.3, 240, 40), {});
  std::vector<MedialMesh> results;
  const int threads_before = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Skeletonizer skeletonizer(Shape(shape), with_target(30));
    skeletonizer.run();
    results.push_back(skeletonizer.medial_mesh());
  }
  omp_set_num_threads(threads_before);
  ASSERT_EQ(results[0].spheres.size(), 30u);
  ASSERT_EQ(results[1].spheres.size(), 30u);
  for (std::size_t i = 0; i < results[0].spheres.size(); ++i) {
    EXPECT_EQ(results[0].spheres[i].center, results[1].spheres[i].center);
    EXPECT_EQ(results[0].spheres[i].radius, results[1].spheres[i].radius);
  }
  EXPECT_EQ(results[0].edges, results[1].edges);
  EXPECT_EQ(results[0].faces, results[1].faces);
}

}  // namespace
}  // namespace vmas
