// Loose checks on the real models and scans in ../shared/data (skipped when it is absent).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>

#include "optimise/connectivity.hpp"
#include "prepare/outliers.hpp"
#include "prepare/normals.hpp"
#include "shared_data.hpp"
#include "test_shapes.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

using test::shared_data;

// Generalised winding number of a closed mesh at `x`: ≈1 inside, ≈0 outside.
double winding_number(const SurfaceInput& mesh, const Vec3& x) {
  double total = 0.0;
  for (const auto& f : mesh.faces) {
    const Vec3 a = mesh.points[f[0]] - x, b = mesh.points[f[1]] - x, c = mesh.points[f[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * M_PI);
}

void expect_valid(const MedialMesh& mesh, std::size_t spheres) {
  ASSERT_EQ(mesh.spheres.size(), spheres);
  for (const Sphere& s : mesh.spheres) {
    EXPECT_TRUE(s.center.allFinite());
    EXPECT_TRUE(std::isfinite(s.radius) && s.radius > 0.0);
  }
  const int n = static_cast<int>(spheres);
  for (const auto& e : mesh.edges) EXPECT_TRUE(e[0] >= 0 && e[0] < n && e[1] >= 0 && e[1] < n);
  for (const auto& f : mesh.faces)
    for (int i : f) EXPECT_TRUE(i >= 0 && i < n);
}

class RealMesh : public ::testing::TestWithParam<std::pair<const char*, int>> {};

TEST_P(RealMesh, PaperSphereCountGivesAValidConnectedSkeletonInsideTheShape) {
  const auto [model, spheres] = GetParam();
  const std::string relative = std::string("meshes/") + model + ".off";
  REQUIRE_SHARED_DATA(relative);
  const SurfaceInput surface = read_surface(shared_data(relative));
  SkeletonizerOptions options;
  options.target.spheres = spheres;
  Skeletonizer skeletonizer(build_shape(surface, {}), options);
  skeletonizer.run();
  const MedialMesh mesh = skeletonizer.medial_mesh();
  expect_valid(mesh, spheres);
  EXPECT_EQ(component_count(mesh), 1);
  for (const Sphere& s : mesh.spheres) EXPECT_GT(winding_number(surface, s.center), 0.5);
}

INSTANTIATE_TEST_SUITE_P(Models, RealMesh,
                         ::testing::Values(std::make_pair("dove", 76), std::make_pair("bear", 45),
                                           std::make_pair("chair", 117)),
                         [](const auto& info) { return std::string(info.param.first); });

// bug at the paper's count: the run alone leaves a leg tip uncovered (ε 0.96 %); the refinement
// moves spheres there and the measured error drops, with the count kept.
TEST(RealMesh, RefinementLowersTheErrorOfBug) {
  REQUIRE_SHARED_DATA("meshes/bug.off");
  const SurfaceInput bug = read_surface(shared_data("meshes/bug.off"));
  Options options;
  options.run.target.spheres = 75;
  const Result refined = skeletonize(bug, options);
  options.refine.max_moves = 0;
  const Result plain = skeletonize(bug, options);
  ASSERT_EQ(refined.medial_mesh.spheres.size(), 75u);
  EXPECT_GE(refined.refine.kept, 1);
  const double before = evaluate(bug, plain.medial_mesh).hausdorff;
  const double after = evaluate(bug, refined.medial_mesh).hausdorff;
  EXPECT_LT(after, 0.95 * before) << before << " -> " << after;
}

// Strongly noisy meshes (the vertices moved by 2-3 % of the diagonal) at the paper's counts:
// every sphere keeps vertices, so no sphere is left unconnected. The ball at a vertex whose
// normal points the wrong way wins no vertex: the final reseeding's later tries pass over such
// donors (they used to give the same ball again, and an empty sphere split the skeleton of
// noisy bug and chair meshes in Table 2; before, one of this test's 8 runs had 3 empty spheres).
TEST(RealMesh, NoisyMeshesLeaveNoSphereWithoutVertices) {
  REQUIRE_SHARED_DATA("meshes/bug.off");
  REQUIRE_SHARED_DATA("meshes/chair.off");
  int runs = 0;
  for (const auto& [model, spheres] : {std::make_pair("bug", 75), std::make_pair("chair", 117)}) {
    const SurfaceInput clean = read_surface(shared_data(std::string("meshes/") + model + ".off"));
    Box box;
    for (const Vec3& p : clean.points) box.extend(p);
    for (const double sigma : {0.02, 0.03}) {
      for (const unsigned seed : {1u, 2u}) {
        SurfaceInput noisy = clean;
        std::mt19937 random(seed);
        std::normal_distribution<double> offset(0.0, sigma * box.diagonal().norm());
        for (Vec3& p : noisy.points) {
          const double x = offset(random), y = offset(random), z = offset(random);
          p += Vec3(x, y, z);
        }
        Options options;
        options.run.target.spheres = spheres;
        options.starts = 1;  // a property of every start (and two take twice as long in CI's
                             // sanitized build)
        const Result result = skeletonize(noisy, options);
        std::vector<int> members(spheres, 0);
        for (int label : result.labels)
          if (label >= 0) ++members[label];
        for (int c = 0; c < spheres; ++c)
          EXPECT_GT(members[c], 0) << model << " sigma " << sigma << " seed " << seed << ": sphere "
                                   << c << " has no vertex";
        EXPECT_EQ(component_count(result.medial_mesh), 1)
            << model << " sigma " << sigma << " seed " << seed;
        ++runs;
      }
    }
  }
  EXPECT_EQ(runs, 8);
}

// `count` points drawn uniformly from the area of `mesh`.
std::vector<Vec3> sample_area(const SurfaceInput& mesh, int count, unsigned seed) {
  std::vector<double> area;
  for (const auto& f : mesh.faces)
    area.push_back((mesh.points[f[1]] - mesh.points[f[0]])
                       .cross(mesh.points[f[2]] - mesh.points[f[0]])
                       .norm());
  std::mt19937 random(seed);
  std::discrete_distribution<std::size_t> face(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const auto& f = mesh.faces[face(random)];
    double u = unit(random), v = unit(random);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    points.push_back(mesh.points[f[0]] + u * (mesh.points[f[1]] - mesh.points[f[0]]) +
                     v * (mesh.points[f[2]] - mesh.points[f[0]]));
  }
  return points;
}

// A random sampling has its own sparse tails (claws, fingers, a chair's thin rails), which the
// statistical outlier rule flags; the sparse-part rule must give every one of them back.
TEST(RealCloud, CleanSamplingsOfTheModelsLoseNoPointToTheOutlierFilter) {
  REQUIRE_SHARED_DATA("meshes/armadillo.off");
  for (const char* model : {"armadillo", "bear", "bug", "chair", "dolphin", "dove", "elephant",
                            "fertility", "pinion", "plane", "santa", "vessel"}) {
    const SurfaceInput mesh = read_surface(shared_data(std::string("meshes/") + model + ".off"));
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const std::vector<Vec3> points = sample_area(mesh, 5000, seed);
      EXPECT_EQ(with_sparse_parts(points, inlier_indices(points, {}), {}).size(), points.size())
          << model << ", seed " << seed;
    }
  }
}

// The chair's seat, back and legs are thinner than noise of 2 % of the diagonal: smoothing merges
// them and balls grow out of the shape (ε 17 % against 9.5 % for the points as they are, in
// Table 2). The skeleton of the unsmoothed points reaches less far past them and is kept.
TEST(RealCloud, SmoothingAThinNoisyShapeIsNoWorseThanTakingItsPointsAsTheyAre) {
  // The chair at σ = 2 %: smoothing folds its legs and back onto single sheets. Before the
  // exterior grids its skeleton then bulged out between the legs and the smoothing check took the
  // points as they are; now the smoothed skeleton stays inside and is kept (6.8 % against 8.3 %).
  REQUIRE_SHARED_DATA("meshes/chair.off");
  const SurfaceInput chair = read_surface(shared_data("meshes/chair.off"));
  SurfaceInput cloud;
  cloud.points = test::with_noise(sample_area(chair, 30000, 3),
                                  0.02 * test::bounding_diagonal(chair.points), 4);
  Options options;
  options.run.target.spheres = 117;
  options.starts = 1;  // one start is enough for the property (two double CI's sanitized time)
  const Result result = skeletonize(cloud, options);
  EXPECT_GT(result.prepare.noise.sigma, 0.01 * result.prepare.diagonal);  // as measured
  EXPECT_TRUE(result.prepare.smoothed());
  const SmoothingCheck& check = result.smoothing_check;
  // The smoothing is kept only when its skeleton reaches past the points as they are by no more
  // than the other's and the noise.
  if (check.made && check.smoothing_kept)
    EXPECT_LE(check.smoothed_reach,
              check.unsmoothed_reach + result.prepare.noise.sigma / result.prepare.diagonal);
  options.prepare.denoise = PrepareOptions::Denoise::Off;
  const double as_they_are = evaluate(chair, skeletonize(cloud, options).medial_mesh).hausdorff;
  const EvalResult chosen = evaluate(chair, result.medial_mesh);
  EXPECT_LT(chosen.hausdorff, as_they_are + 0.003 * chosen.diagonal);
}

TEST(RealScan, MergedBunnyWithoutNormalsGivesAValidSkeleton) {
  REQUIRE_SHARED_DATA("scans/bunny_merged_45k.xyz");
  SurfaceInput cloud = read_surface(shared_data("scans/bunny_merged_45k.xyz"));
  ASSERT_FALSE(cloud.has_normals());
  cloud.normals = estimate_normals(cloud.points, {});
  SkeletonizerOptions options;
  options.target.spheres = 40;
  Skeletonizer skeletonizer(build_shape(cloud, {}), options);
  skeletonizer.run();
  const MedialMesh mesh = skeletonizer.medial_mesh();
  expect_valid(mesh, 40);
  EXPECT_EQ(component_count(mesh), 1);
  // Medial balls of a closed-ish scan are small next to the shape.
  for (const Sphere& s : mesh.spheres) EXPECT_LT(s.radius, 0.5 * skeletonizer.shape().diagonal);
}

// A merged scan straight out of registration with a few dozen strays in one clump far from the
// body (issue 46): the clump goes, and the skeleton measures as the scan alone does.
TEST(RealScan, AStrayClusterBesideTheMergedBunnyIsRemoved) {
  REQUIRE_SHARED_DATA("scans/bunny_merged_45k.xyz");
  SurfaceInput cloud = read_surface(shared_data("scans/bunny_merged_45k.xyz"));
  const Box box = bounding_box(cloud.points);
  const double diagonal = diagonal_of(box);
  const std::size_t scan = cloud.points.size();
  std::mt19937 rng(3);
  std::normal_distribution<double> spread(0.0, 0.004 * diagonal);
  const Vec3 clump = box.max() + 0.2 * diagonal * Vec3(0.3, 0.8, 0.5).normalized();
  for (int i = 0; i < 25; ++i)
    cloud.points.push_back(clump + test::draw_xyz([&] { return spread(rng); }));
  Options options;
  options.run.target.spheres = 40;
  options.starts = 1;
  const Result result = skeletonize(cloud, options);
  EXPECT_EQ(result.prepare.stray_clusters, 1u);
  ASSERT_EQ(result.prepare.stray_points.size(), 25u);
  EXPECT_EQ(result.prepare.stray_points.front(), static_cast<int>(scan));
  for (std::size_t i = scan; i < cloud.points.size(); ++i) EXPECT_EQ(result.labels[i], -1);
  // Without the removal one sphere reaches out to the clump (error about 50 %).
  EXPECT_LT(result.measured_error, 0.06);
}

}  // namespace
}  // namespace vmas
