// Noise estimation, outlier removal, MLS smoothing and input preparation on noisy shapes built
// in code (fixed seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "pipeline/validity.hpp"
#include "prepare/fringe.hpp"
#include "prepare/noise.hpp"
#include "prepare/outliers.hpp"
#include "prepare/prepare.hpp"
#include "prepare/smoothing.hpp"
#include "test_shapes.hpp"
#include "vmas/error.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

using test::Sample;

double rms_distance_to_sphere(const std::vector<Vec3>& points, const Vec3& center, double radius) {
  double sum = 0.0;
  for (const Vec3& p : points) sum += std::pow((p - center).norm() - radius, 2);
  return std::sqrt(sum / points.size());
}

TEST(DenoiseNoise, CleanSamplesAreNotNoisy) {
  const Sample s = test::sample_sphere(Vec3(1, 2, 3), 1.0, 5000, 1);
  const NoiseEstimate noise = estimate_noise(s.points);
  EXPECT_GT(noise.spacing, 0.0);
  EXPECT_FALSE(is_noisy(noise, {})) << "sigma " << noise.sigma << ", spacing " << noise.spacing;
  const auto mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  EXPECT_FALSE(is_noisy(estimate_noise(mesh.points), {}));
}

TEST(DenoiseNoise, EstimateFollowsTheNoise) {
  const Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 2);
  const double diagonal = test::bounding_diagonal(s.points);
  for (double fraction : {0.005, 0.01, 0.02}) {
    const double sigma = fraction * diagonal;
    const NoiseEstimate noise = estimate_noise(test::with_noise(s.points, sigma, 3));
    EXPECT_TRUE(is_noisy(noise, {}));
    EXPECT_GT(noise.sigma, 0.6 * sigma) << "noise " << fraction;
    EXPECT_LT(noise.sigma, 1.4 * sigma) << "noise " << fraction;
  }
}

TEST(DenoiseNoise, RejectsTinyClouds) {
  EXPECT_THROW(estimate_noise(std::vector<Vec3>(10, Vec3::Zero())), InvalidInput);
}

TEST(DenoiseOutliers, RemovesStrayPointsOnly) {
  Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 10000, 4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> box(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) s.points.push_back(test::draw_xyz([&] { return box(rng); }));
  // Strays that happen to fall near the sphere are no outliers; count the others.
  int far_strays = 0;
  for (int i = 10000; i < 10100; ++i) far_strays += std::abs(s.points[i].norm() - 1.0) > 0.1;
  const std::vector<int> kept = with_sparse_parts(s.points, inlier_indices(s.points, {}), {});
  int surface_kept = 0, far_strays_kept = 0;
  for (int i : kept) {
    if (i < 10000)
      ++surface_kept;
    else
      far_strays_kept += std::abs(s.points[i].norm() - 1.0) > 0.1;
  }
  // With strays scattered about, the statistical rule's few sparse surface points go with them.
  EXPECT_GE(surface_kept, 9950);
  EXPECT_LT(far_strays_kept, 0.1 * far_strays);
}

// Among scattered strays, a part of the surface sampled at a third of the density (a cap of the
// sphere, where the statistical rule flags points) still lies on the surface: it stays.
TEST(DenoiseOutliers, ASparsePartStaysAmongStrays) {
  const Sample dense = test::sample_sphere(Vec3::Zero(), 1.0, 12000, 4);
  std::vector<Vec3> points;
  int cap = 0;
  for (std::size_t i = 0; i < dense.points.size(); ++i) {
    const bool in_cap = dense.points[i].z() > 0.95;
    if (in_cap && i % 3 != 0) continue;
    points.push_back(dense.points[i]);
    cap += in_cap;
  }
  const int surface = static_cast<int>(points.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> box(-1.0, 1.0);
  for (int i = 0; i < 150; ++i) points.push_back(test::draw_xyz([&] { return box(rng); }));
  const std::vector<int> inliers = inlier_indices(points, {});
  int cap_flagged = cap;
  for (int i : inliers) cap_flagged -= i < surface && points[i].z() > 0.95;
  ASSERT_GT(cap_flagged, 5) << "the statistical rule must flag part of the cap for this test";
  const std::vector<int> kept = with_sparse_parts(points, inliers, {});
  int cap_kept = 0, far_strays_kept = 0;
  for (int i : kept) {
    if (i < surface)
      cap_kept += points[i].z() > 0.95;
    else
      far_strays_kept += std::abs(points[i].norm() - 1.0) > 0.1;
  }
  EXPECT_GE(cap_kept, cap - 3) << cap_flagged << " of the cap's " << cap << " points flagged";
  EXPECT_LE(far_strays_kept, 2);
}

// A random sampling's sparse tail, creases, a thin wall and the rim of a regular grid are the
// surface sampled more sparsely, not strays.
TEST(DenoiseOutliers, CleanSparseSamplingsLoseNoPoint) {
  const auto expect_whole = [](const std::vector<Vec3>& points, const char* what) {
    EXPECT_EQ(with_sparse_parts(points, inlier_indices(points, {}), {}).size(), points.size())
        << what;
  };
  for (int count : {2000, 5000, 30000}) {
    expect_whole(test::sample_torus(1.0, 0.3, count, 7).points, "torus");
    expect_whole(test::sample_box(Vec3(1.0, 0.6, 0.3), count, 8).points, "box");
    expect_whole(test::sample_ellipsoid(Vec3(1.0, 0.5, 0.02), count, 9).points, "thin ellipsoid");
  }
  std::vector<Vec3> grid;
  for (int i = 0; i < 45; ++i)
    for (int j = 0; j < 45; ++j) grid.emplace_back(0.01 * i, 0.01 * j, 0.0);
  expect_whole(grid, "regular grid");
}

TEST(DenoiseMls, PullsNoisyPointsBackOntoTheSurface) {
  const Vec3 center(1, 2, 3);
  const Sample s = test::sample_sphere(center, 1.0, 10000, 6);
  std::vector<Vec3> points = test::with_noise(s.points, 0.02, 7);
  const double before = rms_distance_to_sphere(points, center, 1.0);
  const std::vector<Vec3> normals = smooth_mls(points, 0.2);
  ASSERT_EQ(normals.size(), points.size());
  EXPECT_LT(rms_distance_to_sphere(points, center, 1.0), 0.3 * before);
  int along_radius = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    along_radius += std::abs(normals[i].dot((points[i] - center).normalized())) > 0.95;
  EXPECT_GT(along_radius, 0.99 * points.size());
}

TEST(DenoiseFringe, NoiseSpreadPastAnEdgeGoesAndASparserPartStays) {
  // A unit square of z = 0 sampled with Gaussian noise (σ = 0.02 on every axis), its right half
  // three times sparser than its left; the smoothing's result simulated by setting z to 0. The
  // noise spreads the points up to 3-4 σ past the square's edges.
  const double sigma = 0.02;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Vec3> raw;
  while (raw.size() < 60000) {
    const Vec3 p(uniform(random), uniform(random), 0.0);
    if (p.x() > 0.5 && uniform(random) > 1.0 / 3.0) continue;
    raw.push_back(p + Vec3(noise(random), noise(random), noise(random)));
  }
  std::vector<Vec3> smoothed = raw;
  for (Vec3& p : smoothed) p.z() = 0.0;
  const std::vector<int> kept = supported_by_noise(smoothed, raw, sigma);
  std::vector<char> is_kept(raw.size(), 0);
  for (int i : kept) is_kept[i] = 1;
  const auto past_edge = [](const Vec3& p) {
    return std::max({-p.x(), p.x() - 1.0, -p.y(), p.y() - 1.0});
  };
  int far_past = 0, far_past_kept = 0, inside = 0, inside_dropped = 0, sparse_inside = 0;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const double beyond = past_edge(smoothed[i]);
    if (beyond > 2.0 * sigma) {
      ++far_past;
      far_past_kept += is_kept[i];
    }
    // Inside, and farther from the density's step than the points compared with.
    if (beyond < -2.0 * sigma && std::abs(smoothed[i].x() - 0.5) > 3.0 * sigma) {
      ++inside;
      inside_dropped += !is_kept[i];
      sparse_inside += smoothed[i].x() > 0.5;
    }
  }
  EXPECT_GT(far_past, 30);
  EXPECT_LE(far_past_kept, far_past / 10);
  // The sparser half too: a point inside goes only when few of the noisy points happen to fall
  // near it (about 22 on average in the sparser half).
  EXPECT_LT(inside_dropped, inside / 1000);
  EXPECT_GT(sparse_inside, 2000);
  EXPECT_GT(kept.size(), 0.95 * raw.size());
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
}

// Two noisy squares 0.08 apart, joined by a row of points (a neck thinner than the noise's
// radius: its middle has under a third of the support of the squares around it), and, when
// `band`, by a full-width band too. Noise along the normal only; the smoothing's result
// simulated by the exact positions.
struct Neck {
  std::vector<Vec3> raw, smoothed;
  std::vector<char> in_neck;
};
Neck squares_joined_by_a_neck(bool band) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.005);
  Neck neck;
  const auto add = [&](const Vec3& p, bool on_neck) {
    neck.smoothed.push_back(p);
    neck.raw.push_back(p + Vec3(0.0, 0.0, noise(random)));
    neck.in_neck.push_back(on_neck);
  };
  for (int i = 0; i < 20000; ++i)  // 40 000 points per unit of area
    add(Vec3(0.5 * uniform(random) + (i % 2) * 0.58, 0.5 * uniform(random), 0.0), false);
  for (int i = 0; i < 12; ++i)  // 0.0067 apart, within any point's 16 nearest
    add(Vec3(0.5 + 0.08 * (i + 0.5) / 12.0, 0.25, 0.0), true);
  if (band)
    for (int i = 0; i < 320; ++i)
      add(Vec3(0.5 + 0.08 * uniform(random), 0.05 + 0.1 * uniform(random), 0.0), false);
  return neck;
}

// The neck's points that `kept` keeps: all of them, and those of its middle (the 6 of 12 that
// have no point of a square within the noise's radius).
std::pair<int, int> neck_points_kept(const Neck& neck, const std::vector<int>& kept) {
  int all = 0, middle = 0;
  for (int i : kept)
    if (neck.in_neck[i]) {
      ++all;
      middle += std::abs(neck.smoothed[i].x() - 0.54) < 0.02;
    }
  return {all, middle};
}

TEST(DenoiseFringe, ATrimThatWouldCutTheDataInTwoRejoinsIt) {
  // With the band, cutting the neck leaves one piece: its middle goes.
  const Neck joined = squares_joined_by_a_neck(true);
  const std::vector<int> kept_joined = supported_by_noise(joined.smoothed, joined.raw, 0.02);
  const auto [joined_neck, joined_middle] = neck_points_kept(joined, kept_joined);
  EXPECT_EQ(joined_middle, 0);
  EXPECT_GT(kept_joined.size(), 0.98 * joined.raw.size());
  // Alone, the neck is the only link: of the points the trim took from it, those that join the
  // squares again come back (the pieces as the shape's graph joins them), the rest of the trim
  // stays.
  const Neck alone = squares_joined_by_a_neck(false);
  const std::vector<int> kept_alone = supported_by_noise(alone.smoothed, alone.raw, 0.02);
  const auto [alone_neck, alone_middle] = neck_points_kept(alone, kept_alone);
  EXPECT_GE(alone_neck, joined_neck + 3);
  EXPECT_GT(alone_middle, 0);
  EXPECT_LT(kept_alone.size(), alone.raw.size());
}

TEST(DenoiseMls, DeviationAtSamplesIsTheSmoothingsOwnAtThosePoints) {
  const Sample s = test::sample_torus(1.0, 0.35, 12000, 12);
  const std::vector<Vec3> noisy = test::with_noise(s.points, 0.015, 13);
  std::vector<Vec3> smoothed = noisy;
  smooth_mls(smoothed, 0.1);
  std::vector<double> moved(noisy.size());
  for (std::size_t i = 0; i < noisy.size(); ++i) moved[i] = (noisy[i] - smoothed[i]).norm();
  const double whole = median(moved) / 0.6745;
  // At every point: the fits made where the points are equal the whole surface's.
  EXPECT_EQ(mls_deviation(noisy, 0.1, static_cast<int>(noisy.size())), whole);
  // At a fifth of them: the same scale (Gaussian noise of 0.015 leaves most of it to remove).
  const double sampled = mls_deviation(noisy, 0.1, 2400);
  EXPECT_NEAR(sampled, whole, 0.05 * whole);
  EXPECT_GT(sampled, 0.6 * 0.015);
  EXPECT_THROW(mls_deviation(noisy, 0.1, 0), std::logic_error);
}

// Fraction of prepared normals that agree in sign with the true ones of the points they came
// from (back in the input's frame).
double agreeing_fraction(const PrepareReport& report, const std::vector<Vec3>& normals,
                         const std::vector<Vec3>& truth) {
  int agreeing = 0;
  for (std::size_t i = 0; i < report.kept.size(); ++i)
    agreeing += report.frame.direction_to_input(normals[i]).dot(truth[report.kept[i]]) > 0.0;
  return static_cast<double>(agreeing) / report.kept.size();
}

TEST(PrepareNoisy, NormalsAgreeInSignAtTwoPercentNoise) {
  const std::vector<std::pair<const char*, Sample>> shapes = {
      {"sphere", test::sample_sphere(Vec3::Zero(), 1.0, 20000, 8)},
      {"torus", test::sample_torus(1.0, 0.35, 30000, 9)},
      {"capsule", test::sample_capsule(0.4, 2.0, 30000, 10)},
      {"thin plate", test::sample_box(Vec3(2.0, 1.0, 0.3), 30000, 11)}};
  for (const auto& [name, shape] : shapes) {
    SurfaceInput input;
    input.points = test::with_noise(shape.points, 0.02 * test::bounding_diagonal(shape.points), 12);
    const PrepareReport report = prepare_surface(input, {});
    EXPECT_GT(report.mls_radius, 0.0) << name;
    EXPECT_TRUE(report.normals_estimated) << name;
    EXPECT_GE(agreeing_fraction(report, input.normals, shape.normals), 0.99) << name;
  }
}

// No sphere reaches out of the capsule by more than the noise explains: the smoothed points keep
// a residual noise (half the noise here) and a sphere can touch one of its peaks, up to 1.6 σ past
// the surface over 24 seeds (`sample_capsule` seeds 100-123); a sphere on a stray or a bulge
// through the surface goes far beyond 2 σ.
TEST(PrepareNoisy, SpheresStayInsideTheCapsule) {
  const double radius = 0.4, length = 2.0;
  const Sample shape = test::sample_capsule(radius, length, 20000, 13);
  SurfaceInput input;
  input.points = test::with_noise(shape.points, 0.01 * test::bounding_diagonal(shape.points), 14);
  const PrepareReport report = prepare_surface(input, {});
  SkeletonizerOptions options;
  options.target.spheres = 10;
  adapt_shrinking_ball(report, options.shrinking_ball);
  Skeletonizer skeletonizer(build_shape(input, {}), options);
  skeletonizer.run();
  const double sigma = report.frame.scale * report.noise.sigma;
  for (const Sphere& s : report.frame.to_input(skeletonizer.medial_mesh()).spheres) {
    const double z = std::clamp(s.center.z(), 0.0, length);
    const double reach = (s.center - Vec3(0.0, 0.0, z)).norm() + s.radius;
    EXPECT_LE(reach, radius + 2.0 * sigma) << "sphere at " << s.center.transpose() << ", radius "
                                     << s.radius;
  }
}

// Local fits read strong noise low; the smoothing's displacement measures it.
TEST(PrepareNoisy, NoiseOfAMeshIsMeasuredAtEveryLevel) {
  const SurfaceInput clean = test::icosphere(Vec3::Zero(), 1.0, 5);
  const double diagonal = test::bounding_diagonal(clean.points);
  for (double fraction : {0.0025, 0.005, 0.01, 0.02, 0.03}) {
    SurfaceInput mesh = clean;
    mesh.points = test::with_noise(clean.points, fraction * diagonal, 22);
    double squares = 0.0;  // the noise as distance to the surface
    for (const Vec3& p : mesh.points) squares += std::pow(p.norm() - 1.0, 2);
    const double sigma = std::sqrt(squares / mesh.points.size());
    const PrepareReport report = prepare_surface(mesh, {});
    EXPECT_GT(report.noise.sigma, 0.75 * sigma) << "noise " << fraction;
    EXPECT_LT(report.noise.sigma, 1.25 * sigma) << "noise " << fraction;
  }
}

// A cloud's noise: local fits in their smallest neighbourhoods can read it low, and smoothing at
// its scale moves the points by more than the noise where the shape is finer than the smoothing's
// support (a tube of 0.25 against a support of 0.43-0.64 at 3 %). The RMS distance to the torus
// is the truth (at 3 % about 7 % above the generating σ: the tube is curved).
TEST(PrepareNoisy, NoiseOfACloudIsMeasuredAtEveryLevel) {
  const double major = 1.0, minor = 0.25;
  const Sample torus = test::sample_torus(major, minor, 30000, 23);
  const double diagonal = test::bounding_diagonal(torus.points);
  for (double fraction : {0.005, 0.01, 0.02, 0.03}) {
    SurfaceInput cloud;
    cloud.points = test::with_noise(torus.points, fraction * diagonal, 24);
    double squares = 0.0;  // the noise as distance to the surface
    for (const Vec3& p : cloud.points) {
      const double ring = std::hypot(p.x(), p.y()) - major;
      squares += std::pow(std::hypot(ring, p.z()) - minor, 2);
    }
    const double sigma = std::sqrt(squares / cloud.points.size());
    const PrepareReport report = prepare_surface(cloud, {});
    ASSERT_TRUE(report.smoothed()) << "noise " << fraction;
    const double measured = report.frame.scale * report.noise.sigma;
    EXPECT_GT(measured, 0.75 * sigma) << "noise " << fraction;
    EXPECT_LT(measured, 1.25 * sigma) << "noise " << fraction;
  }
}

// A support wider than the tube's curvature rounds the tube's fit off toward its core circle: the
// smoothed points sat 0.15 σ (1 %) and 0.49 σ (2 %) inside the torus on average before the
// residuals' local mean was put back, 0.00 and 0.07 σ outside after.
TEST(PrepareNoisy, SmoothingDoesNotShrinkTheShape) {
  const double major = 1.0, minor = 0.25;
  const Sample torus = test::sample_torus(major, minor, 30000, 23);
  const double diagonal = test::bounding_diagonal(torus.points);
  for (double fraction : {0.01, 0.02}) {
    SurfaceInput cloud;
    cloud.points = test::with_noise(torus.points, fraction * diagonal, 24);
    const PrepareReport report = prepare_surface(cloud, {});
    ASSERT_TRUE(report.smoothed()) << "noise " << fraction;
    double offset = 0.0;  // signed distance to the torus, outside positive
    for (const Vec3& working : cloud.points) {
      const Vec3 p = report.frame.to_input(working);
      offset += std::hypot(std::hypot(p.x(), p.y()) - major, p.z()) - minor;
    }
    offset /= static_cast<double>(cloud.points.size());
    EXPECT_LT(std::abs(offset), 0.1 * fraction * diagonal) << "noise " << fraction;
  }
}

// A noisy mesh stays a mesh: every face kept, the vertices pulled back towards the surface, and
// the result judged closed.
TEST(PrepareNoisy, NoisyMeshKeepsItsFacesAndStaysClosed) {
  SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  const double diagonal = test::bounding_diagonal(mesh.points);
  mesh.points = test::with_noise(mesh.points, 0.01 * diagonal, 21);
  const auto rms_off_sphere = [](const std::vector<Vec3>& points) {
    double sum = 0.0;
    for (const Vec3& p : points) sum += std::pow(p.norm() - 1.0, 2);
    return std::sqrt(sum / points.size());
  };
  const double before = rms_off_sphere(mesh.points);
  const std::size_t faces = mesh.faces.size();
  SurfaceInput prepared = mesh;
  const PrepareReport report = prepare_surface(prepared, {});
  EXPECT_GT(report.mesh_smoothing_steps, 0);
  EXPECT_TRUE(report.smoothed());
  EXPECT_EQ(prepared.faces.size(), faces);
  EXPECT_LT(rms_off_sphere(prepared.points), 0.5 * before);

  Options options;
  options.run.target.spheres = 4;
  const Result result = skeletonize(mesh, options);
  EXPECT_GE(result.enclosure, 0.8);
  EXPECT_EQ(result.skeleton_components, 1);
}

TEST(PrepareClean, MeshAndCleanCloudAreLeftAsTheyAre) {
  SurfaceInput mesh = test::icosphere(Vec3::Zero(), 1.0, 4);
  const std::vector<Vec3> vertices = mesh.points;
  const PrepareReport mesh_report = prepare_surface(mesh, {});
  EXPECT_EQ(mesh_report.mls_radius, 0.0);
  ASSERT_EQ(mesh.points.size(), vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    EXPECT_LT((mesh_report.frame.to_input(mesh.points[i]) - vertices[i]).norm(), 1e-12);

  const Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 15);
  SurfaceInput cloud;
  cloud.points = s.points;
  const PrepareReport cloud_report = prepare_surface(cloud, {});
  EXPECT_EQ(cloud_report.mls_radius, 0.0);
  // Random sampling leaves a few sparse spots; the outlier test may drop a handful there.
  EXPECT_LT(cloud_report.outliers, 0.01 * 5000);
  ASSERT_EQ(cloud.points.size(), cloud_report.kept.size());
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    EXPECT_LT((cloud_report.frame.to_input(cloud.points[i]) - s.points[cloud_report.kept[i]]).norm(),
              1e-12);
  EXPECT_GE(agreeing_fraction(cloud_report, cloud.normals, s.normals), 1.0);
}

TEST(PrepareOff, TakesThePointsAsTheyAre) {
  const Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 16);
  SurfaceInput cloud;
  cloud.points = test::with_noise(s.points, 0.02, 17);
  const std::vector<Vec3> noisy = cloud.points;
  PrepareOptions options;
  options.denoise = PrepareOptions::Denoise::Off;
  const PrepareReport report = prepare_surface(cloud, options);
  ASSERT_EQ(report.kept.size(), noisy.size());
  for (std::size_t i = 0; i < noisy.size(); ++i)
    EXPECT_LT((report.frame.to_input(cloud.points[i]) - noisy[i]).norm(), 1e-12);
  EXPECT_TRUE(report.normals_estimated);
}

// A smoothed cloud holds no detail finer than its noise: the run takes its points about 0.7
// noises apart (at least 50 per sphere), every input point still labelled, and whether it
// encloses a volume is judged on all of them.
TEST(PrepareNoisy, ASmoothedCloudRunsOnFewerPointsAndIsStillClosed) {
  const Sample shape = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 15);
  SurfaceInput input;
  input.points = test::with_noise(shape.points, 0.02 * test::bounding_diagonal(shape.points), 16);
  Options options;
  options.run.target.spheres = 20;
  const Result result = skeletonize(input, options);
  const PrepareReport& report = result.prepare;
  ASSERT_TRUE(report.smoothed());
  EXPECT_EQ(report.smoothed_thinned_from + report.outliers, input.points.size());
  EXPECT_LT(report.kept.size(), report.smoothed_thinned_from);
  EXPECT_GE(report.kept.size(), 0.8 * 50 * 20);
  EXPECT_GT(report.smoothed_voxel, 0.0);
  EXPECT_GT(result.enclosure, 0.8);
  EXPECT_EQ(std::count(result.labels.begin(), result.labels.end(), -1),
            static_cast<std::ptrdiff_t>(report.outliers));
  for (const Sphere& s : result.medial_mesh.spheres)
    EXPECT_LE(s.center.norm() + s.radius, 1.0 + 2.0 * 0.02 * test::bounding_diagonal(shape.points));
}

TEST(PrepareNoisy, OnlyASmoothedCloudIsThinnedForItsRun) {
  const Sample shape = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 17);
  SurfaceInput clean;
  clean.points = shape.points;
  const PrepareReport clean_report = prepare_surface(clean, {});
  EXPECT_EQ(smoothed_points_needed(clean, clean_report, 20), clean.points.size());
  SurfaceInput noisy;
  noisy.points = test::with_noise(shape.points, 0.02 * test::bounding_diagonal(shape.points), 18);
  const PrepareReport noisy_report = prepare_surface(noisy, {});
  EXPECT_EQ(smoothed_points_needed(noisy, noisy_report, 0), noisy.points.size());  // unknown
  const std::size_t needed = smoothed_points_needed(noisy, noisy_report, 20);
  EXPECT_LT(needed, noisy.points.size());
  EXPECT_GE(needed, 20u * 50u);
  // Never fewer than 50 points per sphere.
  EXPECT_EQ(smoothed_points_needed(noisy, noisy_report, 1000), noisy.points.size());
}

// Only the normals a smoothed cloud had estimated are checked for small patches inside out: the
// file's normals and a clean cloud's are left as they are.
TEST(PrepareNoisy, OnlyASmoothedCloudsEstimatedNormalsAreTurnedRight) {
  const Sample torus = test::sample_torus(1.0, 0.3, 4000, 53);
  SurfaceInput cloud;
  cloud.points = torus.points;
  cloud.normals = torus.normals;
  std::size_t patch = 0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if ((cloud.points[i] - Vec3(1.3, 0.0, 0.0)).norm() < 0.12) {
      cloud.normals[i] = -cloud.normals[i];
      ++patch;
    }
  ASSERT_GT(patch, 10u);
  const auto turned_right = [&](const PrepareReport& report) {
    SurfaceInput turned = cloud;
    PrepareReport after = report;
    turn_inside_out_normals(turned, after, build_shape(turned, {}));
    EXPECT_EQ(turned.normals == torus.normals ? patch : 0u, after.normals_turned);
    return turned.normals == torus.normals;
  };
  PrepareReport smoothed_and_estimated;
  smoothed_and_estimated.mls_radius = 0.05;
  smoothed_and_estimated.normals_estimated = true;
  EXPECT_TRUE(turned_right(smoothed_and_estimated));
  PrepareReport given = smoothed_and_estimated;
  given.normals_estimated = false;
  EXPECT_FALSE(turned_right(given));
  PrepareReport clean = smoothed_and_estimated;
  clean.mls_radius = 0.0;
  EXPECT_FALSE(turned_right(clean));
}

// A smoothed mesh keeps its vertices (its faces are the surface), and the refinement measures
// on about as many as a smoothed cloud would keep; a clean mesh and a cloud on all their points.
TEST(PrepareNoisy, ASmoothedMeshIsMeasuredOnFewerOfItsVertices) {
  const SurfaceInput clean = test::icosphere(Vec3::Zero(), 1.0, 5);
  SurfaceInput noisy = clean;
  noisy.points = test::with_noise(clean.points, 0.02 * test::bounding_diagonal(clean.points), 19);
  Options options;
  options.run.target.spheres = 20;
  const PreparedShape smoothed = prepare_shape(noisy, options);
  ASSERT_TRUE(smoothed.result.prepare.smoothed());
  ASSERT_TRUE(smoothed.surface.is_mesh());
  EXPECT_EQ(smoothed.surface.points.size(), noisy.points.size());
  const std::size_t budget = refinement_eval_options(smoothed).max_input_points;
  EXPECT_EQ(budget, smoothed_points_needed(smoothed.surface, smoothed.result.prepare, 20));
  EXPECT_LT(budget, noisy.points.size());
  EXPECT_GE(budget, 20u * 50u);

  const PreparedShape sharp = prepare_shape(clean, options);
  ASSERT_FALSE(sharp.result.prepare.smoothed());
  EXPECT_GE(refinement_eval_options(sharp).max_input_points, clean.points.size());
  SurfaceInput cloud;
  cloud.points = noisy.points;
  EXPECT_EQ(refinement_eval_options(prepare_shape(cloud, options)).max_input_points, 0u);
}

}  // namespace
}  // namespace vmas
