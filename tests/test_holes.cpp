// Holes of sampled surfaces (find_holes) on shapes built in code, fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "prepare/holes.hpp"
#include "prepare/prepare.hpp"
#include "test_shapes.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

using test::Sample;

// The points of `s` with z below `height`, normals kept.
Sample cut_below(const Sample& s, double height) {
  Sample kept;
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (s.points[i].z() < height) {
      kept.points.push_back(s.points[i]);
      kept.normals.push_back(s.normals[i]);
    }
  return kept;
}

TEST(Holes, ClosedSamplingsHaveNone) {
  for (int count : {2000, 5000, 30000}) {
    const Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, count, 11);
    EXPECT_TRUE(find_holes(sphere.points, sphere.normals).empty()) << "sphere, " << count;
    const Sample torus = test::sample_torus(1.0, 0.3, count, 12);
    EXPECT_TRUE(find_holes(torus.points, torus.normals).empty()) << "torus, " << count;
    const Sample box = test::sample_box(Vec3(1.0, 0.6, 0.3), count, 13);
    EXPECT_TRUE(find_holes(box.points, box.normals).empty()) << "box, " << count;
    // Two sheets closer than the sample spacing, joined at a sharp rim: a fold, not a hole.
    const Sample plate = test::sample_ellipsoid(Vec3(1.0, 0.5, 0.01), count, 14);
    EXPECT_TRUE(find_holes(plate.points, plate.normals).empty()) << "thin plate, " << count;
  }
}

TEST(Holes, ACapCutOffIsOneHoleAsWideAsTheCut) {
  for (int count : {2000, 30000}) {
    // The cap above z = 0.8 of a unit sphere leaves a circle of radius 0.6.
    const Sample open = cut_below(test::sample_sphere(Vec3::Zero(), 1.0, count, 15), 0.8);
    const std::vector<Hole> holes = find_holes(open.points, open.normals);
    ASSERT_GE(holes.size(), 1u) << count;
    EXPECT_NEAR(holes.front().width, 1.2 * std::sqrt(2.0), 0.25) << count;
    EXPECT_GE(holes.front().rim.size(), 20u) << count;
  }
}

// The lid of a cut sphere's opening lies across the cut (z = 0.8, within the circle of radius 0.6),
// its plane facing away from the points, and the rim's tilt carries over to it.
TEST(Holes, ALidClosesTheOpeningAcrossItsRim) {
  const Sample open = cut_below(test::sample_sphere(Vec3::Zero(), 1.0, 30000, 15), 0.8);
  const std::vector<Hole> holes = find_holes(open.points, open.normals);
  ASSERT_GE(holes.size(), 1u);
  std::vector<Vec3> rim;
  for (int p : holes.front().rim) rim.push_back(open.points[p]);
  const RimPlane plane = rim_plane(rim, open.points);
  EXPECT_GT(plane.outward.z(), 0.99);
  // The rim is the band of points next to the cut, down to a neighbourhood's reach below it.
  EXPECT_GT(plane.radius, 0.58);
  EXPECT_LT(plane.radius, 0.7);
  const std::vector<Vec3> lid = lid_points(rim, plane, 0.02);
  // A disc of the rim's radius in each sector, at most the largest: between the cut's circle
  // (radius 0.6) and the disc of the largest radius.
  EXPECT_GT(static_cast<double>(lid.size()), M_PI * 0.6 * 0.6 / (0.02 * 0.02));
  EXPECT_LT(static_cast<double>(lid.size()), M_PI * plane.radius * plane.radius / (0.02 * 0.02));
  double farthest = 0.0, highest_flat = -1.0;
  for (const Vec3& p : lid) {
    EXPECT_GT(p.z(), 0.72);
    EXPECT_LT(p.z(), 0.81);
    farthest = std::max(farthest, std::hypot(p.x(), p.y()));
    highest_flat = std::max(highest_flat, p.z());
  }
  EXPECT_NEAR(farthest, plane.radius, 0.03);
  // A rim raised on one side (by up to 0.033 at x = 0.66): the lid rises with it there only.
  std::vector<Vec3> tilted = rim;
  for (Vec3& p : tilted)
    if (p.x() > 0.0) p.z() += 0.05 * p.x();
  double highest = -1.0, highest_left = -1.0;
  for (const Vec3& p : lid_points(tilted, plane, 0.02)) {
    highest = std::max(highest, p.z());
    if (p.x() < -0.1) highest_left = std::max(highest_left, p.z());
  }
  EXPECT_NEAR(highest - highest_flat, 0.03, 0.01);
  EXPECT_LE(highest_left, highest_flat + 1e-9);
  EXPECT_TRUE(lid_points({}, plane, 0.02).empty());
}

// The refinement measures a cloud with a hole against its lid, a closed one against its points.
TEST(Holes, TheRefinementClosesACloudsHolesOnly) {
  const auto prepared = [](const Sample& s) {
    SurfaceInput input;
    input.points = s.points;
    return prepare_shape(input);
  };
  const Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 20000, 16);
  const PreparedShape open = prepared(cut_below(sphere, 0.8));
  ASSERT_FALSE(open.result.prepare.holes.empty());
  const std::vector<Vec3> lid = refinement_eval_options(open).lid_points;
  EXPECT_GT(lid.size(), 100u);
  EXPECT_TRUE(refinement_eval_options(prepared(sphere)).lid_points.empty());
}

// A cut across a thin tube (a handle, a vessel's ornament) sampled a few points around: its rim's
// neighbourhoods curve around the tube, thick to their plane (the vessel with its cap cut off,
// or these tubes, lost one or both openings to that) but not to their quadric.
TEST(Holes, ACutAcrossAThinTubeIsFound) {
  struct Tube {
    double major, minor;
    int count;
  };
  for (const Tube& t : {Tube{0.3, 0.03, 4000}, Tube{1.0, 0.04, 10000}}) {
    const Sample tube = test::sample_torus(t.major, t.minor, t.count, 18);
    EXPECT_TRUE(find_holes(tube.points, tube.normals).empty()) << t.minor;
    Sample cut;  // its half below y = 0: two openings across the tube, circles of radius minor
    for (std::size_t i = 0; i < tube.points.size(); ++i)
      if (tube.points[i].y() < 0.0) {
        cut.points.push_back(tube.points[i]);
        cut.normals.push_back(tube.normals[i]);
      }
    const std::vector<Hole> holes = find_holes(cut.points, cut.normals);
    ASSERT_EQ(holes.size(), 2u) << t.minor;
    for (const Hole& hole : holes) EXPECT_NEAR(hole.width, 2.0 * std::sqrt(2.0) * t.minor, 0.02);
  }
}

// Smoothing leaves a noisy cloud's density uneven at the scale of its fits: closed shapes stay
// without holes, and a cap cut off is still found.
TEST(Holes, SmoothedNoisyCloudsHaveHolesOnlyWhereTheyAre) {
  const auto prepared_holes = [](std::vector<Vec3> points, double sigma, unsigned seed) {
    SurfaceInput input;
    input.points = test::with_noise(std::move(points), sigma, seed);
    const PrepareReport report = prepare_surface(input, {});
    EXPECT_TRUE(report.smoothed());
    return report.holes;
  };
  int false_holes = 0;
  for (unsigned seed : {21u, 22u}) {
    const Sample torus = test::sample_torus(1.0, 0.4, 30000, seed);
    const Sample box = test::sample_box(Vec3(1.0, 0.6, 0.4), 30000, seed);
    for (const Sample* shape : {&torus, &box}) {
      const double diagonal = test::bounding_diagonal(shape->points);
      for (double sigma : {0.005, 0.01}) {
        false_holes += !prepared_holes(shape->points, sigma * diagonal, seed).empty();
      }
    }
  }
  EXPECT_EQ(false_holes, 0);
  const Sample open = cut_below(test::sample_sphere(Vec3::Zero(), 1.0, 30000, 24), 0.6);
  EXPECT_FALSE(prepared_holes(open.points, 0.005 * test::bounding_diagonal(open.points), 25).empty());
}

TEST(Holes, TooFewPointsOrNoNormalsFindNothing) {
  const Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 16, 16);
  EXPECT_TRUE(find_holes(s.points, s.normals).empty());
  const Sample t = test::sample_sphere(Vec3::Zero(), 1.0, 100, 17);
  EXPECT_TRUE(find_holes(t.points, {}).empty());
}

}  // namespace
}  // namespace vmas
