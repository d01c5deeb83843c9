// Tests of the shape stage (src/optimise/shape.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "optimise/connectivity.hpp"
#include "optimise/shape.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Shape, MeshAreasSumToSurfaceAreaAndNormalsPointOutward) {
  SurfaceInput input = test::icosphere(Vec3::Zero(), 1.0, 4);
  for (auto& f : input.faces) std::swap(f[1], f[2]);  // inward-oriented input gets flipped
  const Shape shape = build_shape(input, {});
  EXPECT_NEAR(shape.total_area, 4 * M_PI, 0.05);
  for (int v = 0; v < shape.size(); ++v) EXPECT_GT(shape.normals[v].dot(shape.points[v]), 0.99);
  // The neighbour graph is symmetric.
  for (int v = 0; v < shape.size(); ++v)
    for (int i = shape.neighbour_offsets[v]; i < shape.neighbour_offsets[v + 1]; ++i) {
      const int w = shape.neighbours[i];
      const auto begin = shape.neighbours.begin() + shape.neighbour_offsets[w];
      const auto end = shape.neighbours.begin() + shape.neighbour_offsets[w + 1];
      EXPECT_NE(std::find(begin, end, v), end);
    }
}

TEST(Shape, CloudWithoutNormalsIsRejected) {
  SurfaceInput cloud = test::icosphere(Vec3::Zero(), 1.0, 2);
  cloud.faces.clear();
  EXPECT_THROW(build_shape(cloud, {}), InvalidInput);
  ShapeOptions bad;
  bad.k = 1;
  EXPECT_THROW(bad.validate(), InvalidOption);
}

TEST(Shape, ACloudSampledInRowsIsOneGraph) {
  // A cylinder sampled in rings: dense around (spacing ~0.006), sparse along (0.03). Every point's
  // six nearest neighbours lie on its own ring; the rings are one surface all the same.
  SurfaceInput rings;
  for (int ring = 0; ring < 20; ++ring)
    for (int i = 0; i < 100; ++i) {
      const double angle = 2.0 * M_PI * i / 100.0;
      const Vec3 normal(std::cos(angle), std::sin(angle), 0.0);
      rings.points.push_back(0.1 * normal + Vec3(0.0, 0.0, 0.03 * ring));
      rings.normals.push_back(normal);
    }
  ShapeOptions six;
  six.k = 6;
  const Shape shape = build_shape(rings, six);
  EXPECT_EQ(component_count(shape), 1);
  // The bridges are few: the k-NN graph is kept as it is.
  EXPECT_LT(shape.neighbours.size(), 2u * 6u * rings.points.size() + 2u * 40u);
}

// Two parallel plates closer than a coarse cell: the coarse shape keeps their sides apart.
TEST(Shape, CoarsenedShapeKeepsAreaQuadricsAndTheTwoSidesOfAThinPart) {
  SurfaceInput plates;
  const int n = 60;
  for (int side = 0; side < 2; ++side)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        plates.points.push_back(Vec3(i / double(n - 1), j / double(n - 1), side * 0.01));
        plates.normals.push_back(Vec3(0.0, 0.0, side == 0 ? -1.0 : 1.0));
      }
  const Shape shape = build_shape(plates, {});
  const Shape coarse = coarsen_shape(shape, shape.size() / 4);
  EXPECT_LE(coarse.size(), shape.size() / 4);
  EXPECT_GE(coarse.size(), shape.size() / 8);
  double area = 0.0;
  Sqem quadric, coarse_quadric;
  for (int v = 0; v < shape.size(); ++v) quadric += shape.quadric[v];
  for (int v = 0; v < coarse.size(); ++v) {
    area += coarse.area[v];
    coarse_quadric += coarse.quadric[v];
  }
  EXPECT_NEAR(area, shape.total_area, 1e-9 * shape.total_area);
  const Sphere probe{Vec3(0.3, 0.4, 0.2), 0.25};
  EXPECT_NEAR(coarse_quadric(probe), quadric(probe), 1e-9 * std::abs(quadric(probe)));
  // Each side's vertices keep their own normal: no coarse vertex mixes the two plates.
  int down = 0, up = 0;
  for (int v = 0; v < coarse.size(); ++v) (coarse.normals[v].z() < 0.0 ? down : up)++;
  EXPECT_GT(down, coarse.size() / 3);
  EXPECT_GT(up, coarse.size() / 3);
  // The neighbour graph is symmetric, without self loops.
  for (int v = 0; v < coarse.size(); ++v)
    for (int k = coarse.neighbour_offsets[v]; k < coarse.neighbour_offsets[v + 1]; ++k) {
      const int w = coarse.neighbours[k];
      EXPECT_NE(w, v);
      const auto first = coarse.neighbours.begin() + coarse.neighbour_offsets[w];
      const auto last = coarse.neighbours.begin() + coarse.neighbour_offsets[w + 1];
      EXPECT_TRUE(std::find(first, last, v) != last);
    }
  EXPECT_EQ(coarse.blocks.vertices.size(), static_cast<std::size_t>(coarse.size()));
}

}  // namespace
}  // namespace vmas
