// Tests of the partition stage (src/optimise/partition.cpp).
#include <gtest/gtest.h>

#include <random>

#include "optimise/partition.hpp"
#include "test_shapes.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Partition, LabelsEveryVertexWithItsBruteForceMinimum) {
  const Shape shape = build_shape(test::capsule(0.3, 2.0, 8, 24), {});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Sphere> spheres;
  for (int i = 0; i < 12; ++i)
    spheres.push_back({Vec3(0, 0, 2 * uniform(rng)), 0.2 + 0.1 * uniform(rng)});
  std::vector<int> labels;
  std::vector<double> energies;
  partition(shape, spheres, 0.2, labels, energies);
  ASSERT_EQ(labels.size(), static_cast<std::size_t>(shape.size()));
  for (int v = 0; v < shape.size(); ++v) {
    int best = 0;
    for (int m = 1; m < 12; ++m)
      if (vertex_energy(shape, v, spheres[m], 0.2) < vertex_energy(shape, v, spheres[best], 0.2))
        best = m;
    EXPECT_EQ(labels[v], best);
    EXPECT_DOUBLE_EQ(energies[v], vertex_energy(shape, v, spheres[best], 0.2));
  }
}

TEST(Partition, StartingFromPreviousLabelsStillFindsTheMinimum) {
  // The block bounds start from each vertex's previous label; relabel after moving the spheres.
  const Shape shape = build_shape(test::torus(1.0, 0.3, 64, 24), {});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Sphere> spheres;
  for (int i = 0; i < 40; ++i)
    spheres.push_back(
        {test::draw_xyz([&] { return uniform(rng); }).cwiseProduct(Vec3(1.0, 1.0, 0.2)),
         0.2 + 0.1 * uniform(rng)});
  std::vector<int> labels;
  std::vector<double> energies;
  for (int round = 0; round < 3; ++round) {
    partition(shape, spheres, 0.2, labels, energies);
    for (int v = 0; v < shape.size(); ++v) {
      int best = 0;
      for (int m = 1; m < static_cast<int>(spheres.size()); ++m)
        if (vertex_energy(shape, v, spheres[m], 0.2) < vertex_energy(shape, v, spheres[best], 0.2))
          best = m;
      ASSERT_EQ(labels[v], best);
    }
    for (Sphere& s : spheres) s.center += 0.05 * test::draw_xyz([&] { return uniform(rng); });
  }
}

}  // namespace
}  // namespace vmas
