// Properties of the individual stages on shapes built in code.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "test_shapes.hpp"
#include "vmas/connectivity.hpp"
#include "vmas/error.hpp"
#include "vmas/partition.hpp"
#include "vmas/projection.hpp"
#include "vmas/shape.hpp"
#include "vmas/split.hpp"
#include "vmas/sqem.hpp"
#include "vmas/subsample.hpp"
#include "vmas/update.hpp"

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

TEST(Split, ChoosesWorstEligibleNonAdjacentClusters) {
  const std::vector<double> errors = {5, 9, 8, 1, 7};
  // 1–2 adjacent, 2–4 adjacent.
  const std::vector<std::vector<int>> adjacency = {{}, {2}, {1, 4}, {}, {2}};
  const std::vector<bool> eligible(5, true);
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, eligible, 10),
            (std::vector<int>{1, 4, 0, 3}));
  // Eligible: above an error target of 4.
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, {true, true, true, false, true}, 10),
            (std::vector<int>{1, 4, 0}));
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, eligible, 2), (std::vector<int>{1, 4}));
  EXPECT_EQ(select_clusters_to_split(errors, adjacency, {true, false, true, true, true}, 10),
            (std::vector<int>{2, 0, 3}));
}

TEST(Subsample, KeepsAboutTheBudgetOnePointPerCellAndMapsEveryPointToANearbyOne) {
  const test::Sample box = test::sample_box(Vec3(1.0, 2.0, 0.5), 60000, 3);
  const Subsample thin = subsample(box.points, 5000);
  EXPECT_GE(thin.kept.size(), 4000u);
  EXPECT_LE(thin.kept.size(), 5000u);
  ASSERT_EQ(thin.representative.size(), box.points.size());
  EXPECT_TRUE(std::is_sorted(thin.kept.begin(), thin.kept.end()));
  const double cell_diagonal = std::sqrt(3.0) * thin.leaf;
  std::vector<int> represented(thin.kept.size(), 0);
  for (std::size_t i = 0; i < box.points.size(); ++i) {
    const int r = thin.representative[i];
    ASSERT_GE(r, 0);
    ASSERT_LT(r, static_cast<int>(thin.kept.size()));
    ++represented[r];
    EXPECT_LE((box.points[i] - box.points[thin.kept[r]]).norm(), cell_diagonal) << i;
  }
  // A kept point stands for itself, and no two kept points share a cell.
  for (std::size_t j = 0; j < thin.kept.size(); ++j)
    EXPECT_EQ(thin.representative[thin.kept[j]], j);
  std::set<std::array<long, 3>> cells;
  const Vec3 origin = bounding_box(box.points).min();
  for (int k : thin.kept) {
    const Vec3 c = ((box.points[k] - origin) / thin.leaf).array().floor();
    cells.insert({long(c.x()), long(c.y()), long(c.z())});
  }
  EXPECT_EQ(cells.size(), thin.kept.size());
  // The same input gives the same subsample.
  const Subsample again = subsample(box.points, 5000);
  EXPECT_EQ(again.kept, thin.kept);
  EXPECT_EQ(again.representative, thin.representative);
}

TEST(Subsample, SmallCloudsAndAZeroBudgetKeepEveryPoint) {
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 3000, 5);
  for (std::size_t budget : {std::size_t(0), std::size_t(3000), std::size_t(10000)}) {
    const Subsample all = subsample(sphere.points, budget);
    ASSERT_EQ(all.kept.size(), 3000u) << budget;
    EXPECT_EQ(all.leaf, 0.0);
    for (int i = 0; i < 3000; ++i) EXPECT_EQ(all.representative[i], i);
  }
  // Every point at one place, or on a line: still one point per cell, no division by zero.
  const std::vector<Vec3> same(5000, Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(subsample(same, 1000).kept.size(), 1u);
  std::vector<Vec3> line;
  for (int i = 0; i < 5000; ++i) line.push_back(Vec3(i * 1e-3, 0.0, 0.0));
  const Subsample on_line = subsample(line, 1000);
  EXPECT_GE(on_line.kept.size(), 800u);
  EXPECT_LE(on_line.kept.size(), 1000u);
}

TEST(Subsample, PointsOfDifferentGroupsNeverShareACellsPoint) {
  const test::Sample box = test::sample_box(Vec3(1.0, 1.0, 1.0), 20000, 7);
  std::vector<std::uint8_t> groups(box.points.size());
  for (std::size_t i = 0; i < groups.size(); ++i) groups[i] = static_cast<std::uint8_t>(i % 3);
  const Subsample thin = subsample(box.points, 3000, groups);
  EXPECT_GE(thin.kept.size(), 2400u);
  EXPECT_LE(thin.kept.size(), 3000u);
  for (std::size_t i = 0; i < box.points.size(); ++i)
    EXPECT_EQ(groups[thin.kept[thin.representative[i]]], groups[i]) << i;
  EXPECT_THROW(subsample(box.points, 3000, std::vector<std::uint8_t>(5, 0)), InvalidArgument);
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

TEST(Connectivity, SymmetricValidEdgesAndCliqueFaces) {
  const Shape shape = build_shape(test::icosphere(Vec3::Zero(), 1.0, 3), {});
  std::vector<int> labels(shape.size());
  // Octants: 8 clusters; neighbouring octants share a face of the octant cube.
  for (int v = 0; v < shape.size(); ++v) {
    const Vec3& p = shape.points[v];
    labels[v] = (p.x() > 1e-9) + 2 * (p.y() > 1e-9) + 4 * (p.z() > 1e-9);
  }
  const auto adjacency = cluster_adjacency(shape, labels, 8);
  for (int a = 0; a < 8; ++a)
    for (int b : adjacency[a]) {
      EXPECT_NE(a, b);
      EXPECT_TRUE(std::binary_search(adjacency[b].begin(), adjacency[b].end(), a));
    }
  const MedialMesh mesh = build_medial_mesh(std::vector<Sphere>(8), adjacency);
  std::set<std::pair<int, int>> edges;
  for (const auto& e : mesh.edges) {
    EXPECT_LT(e[0], e[1]);
    EXPECT_TRUE(edges.insert({e[0], e[1]}).second);
  }
  for (const auto& f : mesh.faces) {
    EXPECT_TRUE(edges.count({f[0], f[1]}) && edges.count({f[1], f[2]}) &&
                edges.count({f[0], f[2]}));
  }
  // Every octant touches at least its three face-neighbours.
  for (int a = 0; a < 8; ++a) EXPECT_GE(adjacency[a].size(), 3u);
}

}  // namespace
}  // namespace vmas
