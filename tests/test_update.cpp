// Tests of the update stage (src/optimise/update.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "optimise/partition.hpp"
#include "optimise/update.hpp"
#include "test_shapes.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Update, EnergyNeverIncreasesAndFitsTheSphere) {
  const Vec3 center(0.1, 0.2, 0.3);
  const Shape shape = build_shape(test::icosphere(center, 1.0, 3), {});
  std::vector<int> all(shape.size());
  for (int v = 0; v < shape.size(); ++v) all[v] = v;
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss(0.0, 0.3);
  for (int trial = 0; trial < 20; ++trial) {
    Sphere sphere{center + test::draw_xyz([&] { return gauss(rng); }), 0.5 + std::abs(gauss(rng))};
    double energy = cluster_energy(shape, all, sphere, 0.2);
    for (int round = 0; round < 5; ++round) {
      UpdateOptions one_step;
      one_step.max_iterations = 1;
      sphere = fit_sphere(shape, all, sphere, 0.2, one_step);
      const double next = cluster_energy(shape, all, sphere, 0.2);
      EXPECT_LE(next, energy * (1 + 1e-8));  // rounding: the fit sums the quadrics first
      EXPECT_GE(sphere.radius, 0.0);
      energy = next;
    }
    sphere = fit_sphere(shape, all, sphere, 0.2, {});
    EXPECT_LT((sphere.center - center).norm(), 0.01);
    EXPECT_NEAR(sphere.radius, 1.0, 0.01);
  }
}

}  // namespace
}  // namespace vmas
