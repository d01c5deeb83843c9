// Coarse meshes have their faces sampled before the run; dense ones are left as they are.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "core/kdtree.hpp"
#include "prepare/mesh_sampling.hpp"
#include "test_shapes.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

// A closed box [0, size] of twelve triangles, turning outward: long and thin when `size` is.
SurfaceInput coarse_box(const Vec3& size) {
  SurfaceInput box;
  for (int i = 0; i < 8; ++i)
    box.points.emplace_back(i & 1 ? size.x() : 0.0, i & 2 ? size.y() : 0.0, i & 4 ? size.z() : 0.0);
  box.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
               {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return box;
}

// A rod as a CAD exporter writes it: a prism over a regular `sides`-gon, its walls long slivers
// from end to end, its ends fans around a centre vertex.
SurfaceInput coarse_rod(int sides, double radius, double length) {
  SurfaceInput rod;
  for (double z : {0.0, length})
    for (int j = 0; j < sides; ++j) {
      const double a = 2.0 * M_PI * j / sides;
      rod.points.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
  rod.points.emplace_back(0.0, 0.0, 0.0);
  rod.points.emplace_back(0.0, 0.0, length);
  const int bottom = 2 * sides, top = bottom + 1;
  for (int j = 0; j < sides; ++j) {
    const int k = (j + 1) % sides;
    rod.faces.push_back({j, k, sides + k});
    rod.faces.push_back({j, sides + k, sides + j});
    rod.faces.push_back({bottom, k, j});
    rod.faces.push_back({top, sides + j, sides + k});
  }
  return rod;
}

double area_of(const SurfaceInput& mesh) {
  double area = 0.0;
  for (const auto& f : mesh.faces)
    area += 0.5 * (mesh.points[f[1]] - mesh.points[f[0]])
                      .cross(mesh.points[f[2]] - mesh.points[f[0]])
                      .norm();
  return area;
}

double signed_volume_of(const SurfaceInput& mesh) {
  double volume = 0.0;
  for (const auto& f : mesh.faces)
    volume += mesh.points[f[0]].dot(mesh.points[f[1]].cross(mesh.points[f[2]])) / 6.0;
  return volume;
}

// Distance from `p` to the surface of the box [0, size] (p inside or on it).
double distance_to_box_surface(const Vec3& p, const Vec3& size) {
  return p.cwiseMin(size - p).minCoeff();
}

TEST(MeshSampling, ADenseOrWellShapedMeshIsLeftAsItIs) {
  // Dense; and a few hundred vertices, but well-shaped faces (sampling them gave worse skeletons).
  for (const SurfaceInput& mesh :
       {test::icosphere(Vec3::Zero(), 1.0, 5), test::icosphere(Vec3::Zero(), 1.0, 2)}) {
    SurfaceInput sampled = mesh;
    const MeshSampling sampling = sample_coarse_mesh(sampled);
    EXPECT_EQ(sampling.vertices_before, 0u);
    EXPECT_EQ(sampled.points, mesh.points);
    EXPECT_EQ(sampled.faces, mesh.faces);
  }
}

TEST(MeshSampling, ACoarseBoxGetsVerticesAllOverTheSameSurface) {
  const Vec3 size(0.5, 1.0, 6.0);
  const SurfaceInput box = coarse_box(size);
  SurfaceInput sampled = box;
  const MeshSampling sampling = sample_coarse_mesh(sampled);
  ASSERT_EQ(sampling.vertices_before, 8u);
  ASSERT_GT(sampled.points.size(), 5000u);
  EXPECT_LT(sampled.points.size(), 40000u);  // the new vertices keep apart
  for (int i = 0; i < 8; ++i) EXPECT_EQ(sampled.points[i], box.points[i]);
  for (const Vec3& p : sampled.points) EXPECT_LT(distance_to_box_surface(p, size), 1e-12);
  // The same closed surface, turning the same way.
  EXPECT_NEAR(area_of(sampled), area_of(box), 1e-9);
  EXPECT_NEAR(signed_volume_of(sampled), signed_volume_of(box), 1e-9);
  EXPECT_TRUE(mesh_defects(sampled.faces).closed());
  // Every point of the surface near a vertex: random points on the box's faces.
  const KdTree vertices(sampled.points);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double farthest = 0.0;
  for (int i = 0; i < 3000; ++i) {
    Vec3 p(unit(rng) * size.x(), unit(rng) * size.y(), unit(rng) * size.z());
    const int axis = i % 3;
    p[axis] = (i / 3) % 2 ? size[axis] : 0.0;
    farthest = std::max(farthest, (sampled.points[vertices.nearest(p)] - p).norm());
  }
  EXPECT_LT(farthest, sampling.edge_limit);
}

TEST(MeshSampling, BothSidesOfAThinWallGetVertices) {
  const double thickness = 0.002;
  SurfaceInput slab = coarse_box(Vec3(6.0, 1.0, thickness));
  ASSERT_GT(sample_coarse_mesh(slab).vertices_before, 0u);
  int below = 0, above = 0;
  for (const Vec3& p : slab.points) {
    below += p.z() == 0.0;
    above += p.z() == thickness;
  }
  EXPECT_GT(below, 1000);
  // Comparable (the two sides' triangulations differ); a vertex across the wall must not
  // stand for one on this side.
  EXPECT_GT(above, 0.6 * below);
  EXPECT_GT(below, 0.6 * above);
}

TEST(MeshSampling, ALowPolyMeshIsSampledNotSmoothed) {
  // A cube of eight vertices: well-shaped faces, but too few vertices for any sphere count.
  SurfaceInput cube = coarse_box(Vec3(1.0, 1.0, 1.0));
  EXPECT_EQ(sample_coarse_mesh(cube).vertices_before, 8u);
  // A 128-vertex torus: its 16-vertex neighbourhoods span its bends, which read as noise of
  // about 40 % of its spacing; smoothing that would shrink the tube, not denoise it.
  const SurfaceInput torus = test::torus(1.0, 0.4, 16, 8);
  Options options;
  options.run.target.spheres = 16;
  const Result result = skeletonize(torus, options);
  EXPECT_TRUE(result.prepare.noise_from_facets);
  EXPECT_FALSE(result.prepare.smoothed());
  EXPECT_EQ(result.prepare.mesh_sampled_from, torus.points.size());
  EXPECT_EQ(result.skeleton_components, 1);
  const double error = evaluate(torus, result.medial_mesh).hausdorff / result.prepare.diagonal;
  std::cout << "128-vertex torus at 16 spheres, error / diagonal: " << error << "\n";
  EXPECT_LT(error, 0.03);
  // A dense torus's noise reading is its own.
  const Result dense = skeletonize(test::torus(1.0, 0.4, 96, 48), options);
  EXPECT_FALSE(dense.prepare.noise_from_facets);
  EXPECT_EQ(dense.prepare.mesh_sampled_from, 0u);
}

TEST(MeshSampling, ACoarseRodGetsAMedialSkeleton) {
  const SurfaceInput rod = coarse_rod(24, 0.1, 2.0);
  Options options;
  options.run.target.spheres = 12;
  const Result sampled = skeletonize(rod, options);
  options.prepare.sample_coarse_meshes = false;
  const Result as_given = skeletonize(rod, options);
  EXPECT_EQ(sampled.prepare.mesh_sampled_from, rod.points.size());
  EXPECT_GT(sampled.prepare.mesh_sampled_to, 10 * rod.points.size());
  EXPECT_EQ(as_given.prepare.mesh_sampled_from, 0u);
  // Every input vertex labelled, none of the sampled ones (they are no input rows).
  ASSERT_EQ(sampled.labels.size(), rod.points.size());
  for (int label : sampled.labels) EXPECT_GE(label, 0);
  EXPECT_TRUE(sampled.invalid_spheres.checked);
  EXPECT_EQ(sampled.invalid_spheres.outside, 0u);
  EXPECT_EQ(sampled.invalid_spheres.radius_off, 0u);
  // Measured the same way (the faces sampled): the vertices as given leave most of the walls
  // unseen.
  const double sampled_error = evaluate(rod, sampled.medial_mesh).hausdorff;
  const double given_error = evaluate(rod, as_given.medial_mesh).hausdorff;
  std::cout << "rod at 12 spheres, error / diagonal: " << sampled_error / sampled.prepare.diagonal
            << " sampled, " << given_error / as_given.prepare.diagonal << " as given\n";
  EXPECT_LT(sampled_error, 0.7 * given_error);
}

}  // namespace
}  // namespace vmas
