// The one-call API (vmas/vmas.hpp): labels per input point, cancellation, the thread count as
// an option, warnings as data, options named as the CLI spells them.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "optimise/projection.hpp"
#include "refine/refine.hpp"
#include "test_shapes.hpp"
#include "vmas/eval.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

// The message of the warning `code`; empty when there is none.
std::string warning_message(const Result& result, const std::string& code) {
  for (const Warning& w : result.warnings)
    if (w.code == code) return w.message;
  return {};
}

bool has_warning(const Result& result, const std::string& code) {
  return !warning_message(result, code).empty();
}

SurfaceInput capsule_cloud() {
  const test::Sample s = test::sample_capsule(0.2, 1.0, 3000, 41);
  SurfaceInput cloud;
  cloud.points = s.points;
  return cloud;
}

TEST(OneCall, LabelsIndexTheInputPointsWithMinusOneForDroppedOnes) {
  SurfaceInput cloud = capsule_cloud();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // An organised scan's "no point here", and a point seen twice.
  cloud.points.insert(cloud.points.begin() + 10, Vec3(nan, nan, nan));
  cloud.points.push_back(cloud.points[20]);
  Options options;
  options.run.target.spheres = 6;
  const Result result = skeletonize(cloud, options);
  ASSERT_EQ(result.medial_mesh.spheres.size(), 6u);
  ASSERT_EQ(result.labels.size(), cloud.points.size());
  EXPECT_EQ(result.labels[10], -1);
  EXPECT_EQ(result.labels.back(), -1);
  EXPECT_EQ(result.clean.non_finite_points, 1u);
  EXPECT_EQ(result.clean.duplicate_points, 1u);
  // Every other point is in a cluster, unless outlier removal took it.
  std::vector<int> sizes(6, 0);
  std::size_t unlabelled = 0;
  for (std::size_t i = 0; i < result.labels.size(); ++i) {
    ASSERT_GE(result.labels[i], -1) << i;
    ASSERT_LT(result.labels[i], 6) << i;
    if (result.labels[i] >= 0)
      ++sizes[result.labels[i]];
    else
      ++unlabelled;
  }
  EXPECT_EQ(unlabelled, 2 + result.prepare.outliers);
  for (int size : sizes) EXPECT_GT(size, 0);
  // A point's sphere is near it: the capsule is 0.2 thick.
  for (std::size_t i = 0; i < cloud.points.size(); i += 97)
    if (result.labels[i] >= 0) {
      const Sphere& s = result.medial_mesh.spheres[result.labels[i]];
      EXPECT_LT((cloud.points[i] - s.center).norm() - s.radius, 0.1) << i;
    }
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front().message;
  EXPECT_EQ(result.skeleton_components, 1);
}

TEST(OneCall, AThinnedCloudStillLabelsEveryInputPoint) {
  const test::Sample s = test::sample_capsule(0.2, 1.0, 12000, 43);
  SurfaceInput cloud;
  cloud.points = s.points;
  Options options;
  options.run.target.spheres = 8;
  options.prepare.max_points = 3000;
  const Result result = skeletonize(cloud, options);
  EXPECT_EQ(result.prepare.thinned_from, 12000u);
  EXPECT_LE(result.prepare.kept.size(), 3000u);
  EXPECT_GT(result.prepare.voxel, 0.0);
  ASSERT_EQ(result.labels.size(), cloud.points.size());
  std::vector<int> sizes(8, 0);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const int label = result.labels[i];
    ASSERT_GE(label, -1) << i;
    ASSERT_LT(label, 8) << i;
    if (label < 0) continue;
    ++sizes[label];
    // The label of a point that did not take part is its voxel's point's: its sphere is near.
    const Sphere& sphere = result.medial_mesh.spheres[label];
    EXPECT_LT((cloud.points[i] - sphere.center).norm() - sphere.radius, 0.1) << i;
  }
  for (int size : sizes) EXPECT_GT(size, 12000 / 8 / 10);
  // Only the voxels of outliers lose their label.
  EXPECT_LE(std::count(result.labels.begin(), result.labels.end(), -1),
            static_cast<long>(20 * result.prepare.outliers));
  options.prepare.max_points = 999;
  EXPECT_THROW(skeletonize(cloud, options), InvalidOption);
}

TEST(OneCall, ReportsEveryPhaseAndCancelsWhenTheCallbackSaysSo) {
  const SurfaceInput cloud = capsule_cloud();
  Options options;
  options.run.target.spheres = 4;
  bool preparing = false, optimising = false;
  int last_round = 0, rounds = 0;
  skeletonize(cloud, options, [&](const Progress& p) {
    preparing = preparing || p.phase == Progress::Phase::Preparing;
    optimising = optimising || p.phase == Progress::Phase::Optimising;
    if (p.phase == Progress::Phase::Optimising) EXPECT_EQ(p.target_spheres, 4);
    if (p.phase == Progress::Phase::FinalRefit) {
      last_round = p.round;
      rounds = p.rounds;
    }
    return true;
  });
  EXPECT_TRUE(preparing);
  EXPECT_TRUE(optimising);
  EXPECT_EQ(rounds, options.run.final_rounds);
  EXPECT_EQ(last_round, options.run.final_rounds);

  int steps = 0;
  EXPECT_THROW(skeletonize(cloud, options,
                           [&](const Progress& p) {
                             steps += p.phase == Progress::Phase::Optimising;
                             return steps < 3;
                           }),
               Cancelled);
  EXPECT_EQ(steps, 3);
  EXPECT_THROW(skeletonize(cloud, options, [](const Progress&) { return false; }), Cancelled);
}

// What a run's progress reports said: the phases in the order they came (each once), and the
// fractions of each.
struct PhaseLog {
  std::vector<Progress::Phase> order;
  std::map<Progress::Phase, std::vector<double>> fractions;

  bool operator()(const Progress& p) {
    if (order.empty() || order.back() != p.phase) order.push_back(p.phase);
    fractions[p.phase].push_back(p.fraction);
    return true;
  }
};

// Every phase comes once, in the documented order, and its fraction rises from where it starts
// to 1 (Progress).
void expect_each_phase_rises_once_to_one(const PhaseLog& log) {
  EXPECT_TRUE(std::is_sorted(log.order.begin(), log.order.end()));
  EXPECT_EQ(std::adjacent_find(log.order.begin(), log.order.end()), log.order.end());
  for (const auto& [phase, fractions] : log.fractions) {
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end())) << static_cast<int>(phase);
    EXPECT_GE(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0) << static_cast<int>(phase);
  }
}

TEST(OneCall, EveryPhasesFractionRisesFromZeroToOneOnce) {
  const SurfaceInput cloud = capsule_cloud();
  Options options;
  options.run.target.spheres = 6;
  for (int threads : {1, 2}) {  // the second start after the first, or beside it
    options.threads = threads;
    PhaseLog log;
    skeletonize(cloud, options, std::ref(log));
    expect_each_phase_rises_once_to_one(log);
    using Phase = Progress::Phase;
    for (Phase phase : {Phase::Preparing, Phase::Optimising, Phase::Settling, Phase::FinalRefit,
                        Phase::Refining, Phase::OtherStarts})
      EXPECT_EQ(log.fractions.count(phase), 1u) << threads << " " << static_cast<int>(phase);
  }
  // An error threshold: Optimising rises with the worst cluster's error.
  options.run.target = Target{};
  options.run.target.error = 0.02;
  PhaseLog log;
  skeletonize(cloud, options, std::ref(log));
  expect_each_phase_rises_once_to_one(log);
  EXPECT_GT(log.fractions[Progress::Phase::Optimising].size(), 2u);
  // Cancelled while the second start runs after the first.
  options.threads = 1;
  const auto until_other_starts = [](const Progress& p) {
    return p.phase != Progress::Phase::OtherStarts;
  };
  EXPECT_THROW(skeletonize(cloud, options, until_other_starts), Cancelled);
}

SurfaceInput box_cloud() {
  const test::Sample s = test::sample_box(Vec3(1.0, 0.6, 0.3), 20000, 3);
  SurfaceInput cloud;
  cloud.points = s.points;
  cloud.normals = s.normals;
  return cloud;
}

// The refinement after the run: on this box the run leaves corners worse served than they need
// to be, and moves that lower the measured error exist.
TEST(Refine, KeepsOnlyMovesThatLowerTheMeasuredErrorAndTheExactCount) {
  const SurfaceInput box = box_cloud();
  Options options;
  options.run.target.spheres = 12;
  const Result refined = skeletonize(box, options);
  options.refine.max_moves = 0;
  const Result plain = skeletonize(box, options);
  EXPECT_EQ(plain.refine.tried, 0);
  ASSERT_EQ(refined.medial_mesh.spheres.size(), 12u);
  EXPECT_GE(refined.refine.kept, 1);
  EXPECT_LE(refined.refine.kept, refined.refine.tried);
  EXPECT_LT(refined.refine.error_after, refined.refine.error_before);
  // The same metric from outside (vmas eval): lower too.
  EXPECT_LT(evaluate(box, refined.medial_mesh).hausdorff,
            evaluate(box, plain.medial_mesh).hausdorff);
  // No move is kept past max_moves.
  options.refine.max_moves = 1;
  EXPECT_LE(skeletonize(box, options).refine.tried, 1);
}

// A move whose new sphere is one already there (a bulge made by one sphere projects onto it) is
// not made: on this capsule, at 3 to 5 spheres, such moves left two spheres at one place.
TEST(Refine, NeverPutsTwoSpheresAtOnePlace) {
  const SurfaceInput capsule = test::capsule(0.2, 1.0, 8, 24);
  for (int count = 3; count <= 5; ++count) {
    SkeletonizerOptions options;
    options.target.spheres = count;
    Skeletonizer skeletonizer(build_shape(capsule, {}), options);
    skeletonizer.run();
    refine_worst_served(skeletonizer, capsule, RefineOptions{});
    const std::vector<Sphere>& spheres = skeletonizer.spheres();
    ASSERT_EQ(spheres.size(), static_cast<std::size_t>(count));
    for (std::size_t a = 0; a < spheres.size(); ++a)
      for (std::size_t b = a + 1; b < spheres.size(); ++b)
        EXPECT_GT((spheres[a].center - spheres[b].center).norm(), 1e-3)
            << count << " spheres: " << a << " and " << b;
  }
}

// The two results have the same spheres, bit for bit.
void expect_same_spheres(const Result& a, const Result& b) {
  ASSERT_EQ(a.medial_mesh.spheres.size(), b.medial_mesh.spheres.size());
  for (std::size_t i = 0; i < a.medial_mesh.spheres.size(); ++i) {
    EXPECT_EQ(a.medial_mesh.spheres[i].center, b.medial_mesh.spheres[i].center);
    EXPECT_EQ(a.medial_mesh.spheres[i].radius, b.medial_mesh.spheres[i].radius);
  }
}

TEST(Refine, SameResultWithOneAndTwoThreadsAndCancellable) {
  const SurfaceInput box = box_cloud();
  Options options;
  options.run.target.spheres = 12;
  options.threads = 1;
  const Result one = skeletonize(box, options);
  options.threads = 2;
  const Result two = skeletonize(box, options);
  expect_same_spheres(one, two);
  EXPECT_EQ(one.medial_mesh.edges, two.medial_mesh.edges);
  EXPECT_EQ(one.refine.kept, two.refine.kept);

  int moves = 0, rounds = 0;
  EXPECT_THROW(skeletonize(box, options,
                           [&](const Progress& p) {
                             if (p.phase != Progress::Phase::Refining) return true;
                             ++moves;
                             rounds = p.rounds;
                             EXPECT_GT(p.error, 0.0);
                             return false;
                           }),
               Cancelled);
  EXPECT_EQ(moves, 1);
  EXPECT_EQ(rounds, options.refine.max_moves);
  options.refine.max_moves = -1;
  EXPECT_THROW(skeletonize(box, options), InvalidOption);
}

// A similarity transform of the input moves the skeleton with it and changes nothing else: the
// working frame is the shape's own (issue 18). A mesh and a random cloud without normals of a
// shape with three different spreads (an egg with a bump), so that its principal axes are
// defined. (The vertices of the mesh as a cloud would not do: their neighbours lie at exactly
// equal distances, and rounding decides among them.)
TEST(OneCall, ASkeletonMovesWithItsInput) {
  const auto bumped = [](const Vec3& p) {
    return Vec3(p.x() + 0.3 * std::pow(std::max(p.y(), 0.0), 2), 0.6 * p.y(), 0.35 * p.z());
  };
  SurfaceInput egg = test::icosphere(Vec3::Zero(), 1.0, 4);
  for (Vec3& p : egg.points) p = bumped(p);
  SurfaceInput egg_cloud;
  for (const Vec3& p : test::sample_sphere(Vec3::Zero(), 1.0, 4000, 7).points)
    egg_cloud.points.push_back(bumped(p));
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const double scale = 3.7;
  const Vec3 offset(5.0, -2.0, 11.0);
  for (const SurfaceInput* input : {&egg, &egg_cloud}) {
    SurfaceInput moved = *input;
    for (Vec3& p : moved.points) p = scale * (rotation * p) + offset;
    Options options;
    options.run.target.spheres = 12;
    const Result here = skeletonize(*input, options);
    const Result there = skeletonize(moved, options);
    const char* kind = input->is_mesh() ? "mesh" : "cloud";
    ASSERT_EQ(there.medial_mesh.spheres.size(), here.medial_mesh.spheres.size()) << kind;
    const double diagonal = test::bounding_diagonal(input->points);
    for (std::size_t i = 0; i < here.medial_mesh.spheres.size(); ++i) {
      const Sphere& a = here.medial_mesh.spheres[i];
      const Sphere& b = there.medial_mesh.spheres[i];
      const Vec3 back = rotation.transpose() * (b.center - offset) / scale;
      EXPECT_LT((back - a.center).norm(), 1e-6 * diagonal) << kind << " sphere " << i;
      EXPECT_NEAR(b.radius / scale, a.radius, 1e-6 * diagonal) << kind << " sphere " << i;
    }
    EXPECT_EQ(there.medial_mesh.edges, here.medial_mesh.edges) << kind;
    EXPECT_EQ(there.skeleton_components, here.skeleton_components) << kind;
    EXPECT_EQ(there.labels, here.labels) << kind;
  }
}

// Two starts run side by side when the call has two threads, one after the other with one: the
// same result either way, and the start kept is the one with the least measured error (neither
// splits this capsule's skeleton).
TEST(OneCall, StartsSideBySideOrOneAfterTheOtherGiveTheSameResult) {
  const SurfaceInput cloud = capsule_cloud();
  Options options;
  options.run.target.spheres = 6;
  options.threads = 2;
  const Result side_by_side = skeletonize(cloud, options);
  options.threads = 1;
  const Result in_turn = skeletonize(cloud, options);
  expect_same_spheres(side_by_side, in_turn);
  EXPECT_EQ(side_by_side.labels, in_turn.labels);
  ASSERT_EQ(in_turn.start_errors.size(), 2u);
  EXPECT_EQ(side_by_side.start_errors, in_turn.start_errors);
  EXPECT_EQ(in_turn.measured_error, in_turn.start_errors[in_turn.start_kept]);
  EXPECT_EQ(in_turn.measured_error,
            *std::min_element(in_turn.start_errors.begin(), in_turn.start_errors.end()));
  options.starts = 0;
  EXPECT_THROW(skeletonize(cloud, options), InvalidOption);
  options.starts = kMaxStarts + 1;
  EXPECT_THROW(skeletonize(cloud, options), InvalidOption);
}

TEST(OneCall, ThreadCountIsAnOptionNotGlobalState) {
  const SurfaceInput cloud = capsule_cloud();
  const int previous = omp_get_max_threads();
  omp_set_num_threads(1);
  Options options;
  options.run.target.spheres = 3;
  options.starts = 1;  // one optimisation, with every thread of the call
  int seen = 0;
  const auto watch = [&](const Progress&) {
    seen = omp_get_max_threads();
    return true;
  };
  options.threads = omp_get_num_procs();
  skeletonize(cloud, options, watch);
  EXPECT_EQ(seen, omp_get_num_procs());
  EXPECT_EQ(omp_get_max_threads(), 1);
  // More threads than cores are capped at the cores.
  options.threads = 1000;
  skeletonize(cloud, options, watch);
  EXPECT_EQ(seen, omp_get_num_procs());
  EXPECT_EQ(omp_get_max_threads(), 1);
  omp_set_num_threads(previous);
}

TEST(OneCall, OptionErrorsNameTheOption) {
  const SurfaceInput cloud = capsule_cloud();
  Options options;
  options.run.lambda = -1.0;
  try {
    skeletonize(cloud, options);
    ADD_FAILURE() << "no InvalidOption";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "run.lambda");
    EXPECT_EQ(e.problem(), "must be in [0, 1e6] (got -1.000000)");
    EXPECT_EQ(std::string(e.what()).rfind("run.lambda must", 0), 0u) << e.what();
  }
  options = Options();
  options.prepare.normals.k = 1;  // two levels down
  try {
    skeletonize(cloud, options);
    ADD_FAILURE() << "no InvalidOption";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.option(), "prepare.normals.k");
  }
  options = Options();
  options.run.target.spheres = 10;
  options.run.target.error = 0.01;
  EXPECT_THROW(skeletonize(cloud, options), InvalidOption);
  options = Options();
  options.run.target.spheres = 5000;  // more than the 3000 points
  EXPECT_THROW(skeletonize(cloud, options), InvalidOption);
}

// Every option struct's own checks name their field, so each reaches the caller as a path.
TEST(OneCall, EveryNestedOptionErrorNamesItsField) {
  const auto path_of = [](const Options& options) {
    try {
      options.validate();
    } catch (const InvalidOption& e) {
      return e.option();
    }
    return std::string("(valid)");
  };
  Options options;
  options.run.split.max_fraction = 2.0;
  EXPECT_EQ(path_of(options), "run.split.max_fraction");
  options = Options();
  options.run.update.max_iterations = 0;
  EXPECT_EQ(path_of(options), "run.update.max_iterations");
  options = Options();
  options.run.shrinking_ball.box_margin = -1.0;
  EXPECT_EQ(path_of(options), "run.shrinking_ball.box_margin");
  options = Options();
  options.run.min_cluster_size = 0;
  EXPECT_EQ(path_of(options), "run.min_cluster_size");
  options = Options();
  options.prepare.noise.outlier_k = 1;
  EXPECT_EQ(path_of(options), "prepare.noise.outlier_k");
}

TEST(OneCall, DefaultsToTheCliSphereCountAndHonoursAnErrorThreshold) {
  const SurfaceInput cloud = capsule_cloud();
  EXPECT_EQ(skeletonize(cloud).medial_mesh.spheres.size(), std::size_t(kDefaultSpheres));
  Options options;
  options.run.target.error = 0.02;
  const Result result = skeletonize(cloud, options);
  EXPECT_GT(result.medial_mesh.spheres.size(), 1u);
  EXPECT_LT(result.medial_mesh.spheres.size(), 60u);
}

TEST(OneCallWarnings, OpenMeshAndMisorientedFaces) {
  SurfaceInput sphere = test::icosphere(Vec3::Zero(), 1.0, 3);
  Options options;
  options.run.target.spheres = 3;
  const Result closed = skeletonize(sphere, options);
  EXPECT_TRUE(closed.warnings.empty()) << closed.warnings.front().message;
  EXPECT_EQ(closed.mesh_defects.boundary_edges, 0u);

  SurfaceInput open = sphere;
  open.faces.erase(std::remove_if(open.faces.begin(), open.faces.end(),
                                  [&](const auto& f) { return open.points[f[0]].z() > 0.6; }),
                   open.faces.end());
  const Result opened = skeletonize(open, options);
  EXPECT_GT(opened.mesh_defects.boundary_edges, 0u);
  EXPECT_TRUE(has_warning(opened, "open-mesh"));

  SurfaceInput flipped = sphere;
  for (std::size_t f = 0; f < flipped.faces.size(); f += 2)
    std::swap(flipped.faces[f][1], flipped.faces[f][2]);
  const Result misoriented = skeletonize(flipped, options);
  EXPECT_GT(misoriented.mesh_defects.misoriented_edges, 0u);
  EXPECT_TRUE(has_warning(misoriented, "misoriented-faces"));
}

TEST(OneCallWarnings, InwardNormalsAndOpenScans) {
  SurfaceInput cloud = capsule_cloud();
  for (const Vec3& p : cloud.points) {
    // The capsule's outward normal, reversed.
    const Vec3 axis_point(0.0, 0.0, std::clamp(p.z(), 0.0, 1.0));
    cloud.normals.push_back((axis_point - p).normalized());
  }
  Options options;
  options.run.target.spheres = 3;
  EXPECT_TRUE(has_warning(skeletonize(cloud, options), "inward-normals"));
  options.prepare.orient_normals = true;
  EXPECT_FALSE(has_warning(skeletonize(cloud, options), "inward-normals"));

  SurfaceInput half;
  for (const Vec3& p : test::sample_sphere(Vec3::Zero(), 1.0, 3000, 42).points)
    if (p.z() > 0.0) half.points.push_back(p);
  options = Options();
  options.run.target.spheres = 3;
  const Result scan = skeletonize(half, options);
  EXPECT_LT(scan.enclosure, MedialProjector::kEnclosed);
  EXPECT_TRUE(has_warning(scan, "open-surface"));
  EXPECT_EQ(warning_message(scan, "open-surface").find("smoothing"), std::string::npos);
}

// A closed plate thinner than its noise: the smoothing merges its faces into one sheet, which
// encloses nothing, and the warning says that this may be why.
TEST(OneCallWarnings, OpenSurfaceOnSmoothedDataNamesMergedThinParts) {
  SurfaceInput plate;
  plate.points = test::sample_box(Vec3(2.0, 2.0, 0.02), 20000, 43).points;
  plate.points = test::with_noise(plate.points, 0.01 * test::bounding_diagonal(plate.points), 44);
  Options options;
  options.run.target.spheres = 10;
  const Result result = skeletonize(plate, options);
  ASSERT_TRUE(result.prepare.smoothed());
  EXPECT_LT(result.enclosure, MedialProjector::kEnclosed);
  EXPECT_NE(warning_message(result, "open-surface").find("thinner than the smoothing radius"),
            std::string::npos);
}

// A unit sphere with a thin spike (radius 0.01, from z = 0.9 to 2.4): 5 000 points by area, of
// which the spike gets about 37, each coordinate with Gaussian noise of `sigma` × the diagonal.
SurfaceInput noisy_sphere_with_spike(double sigma, bool spike) {
  constexpr double kRadius = 0.01, kFrom = 0.9, kLength = 1.5;
  constexpr int kCount = 5000;
  const double sphere_area = 4.0 * M_PI, spike_area = 2.0 * M_PI * kRadius * kLength;
  const int on_spike =
      spike ? static_cast<int>(std::lround(kCount * spike_area / (sphere_area + spike_area))) : 0;
  SurfaceInput cloud;
  cloud.points = test::sample_sphere(Vec3::Zero(), 1.0, kCount - on_spike, 51).points;
  std::mt19937 rng(52);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < on_spike; ++i) {
    const double angle = 2.0 * M_PI * uniform(rng), height = kFrom + kLength * uniform(rng);
    cloud.points.emplace_back(kRadius * std::cos(angle), kRadius * std::sin(angle), height);
  }
  cloud.points = test::with_noise(cloud.points, sigma * test::bounding_diagonal(cloud.points), 53);
  return cloud;
}

// The outlier filter takes the spike's sparse points away with the noise's tails, and a second
// pass on them as they are once took them away too (the skeleton lay 28 % of the diagonal from
// the spike's tip): now the points as they are are skeletonized without the filter, and their
// skeleton, which reaches the tip, is kept. Without the spike, noise alone does not call for the
// check.
TEST(SmoothingCheck, APartTheSmoothingTookAwayBringsBackThePointsAsTheyAre) {
  Options options;
  options.run.target.spheres = 30;
  options.starts = 1;  // one start is enough for the property (and for the sanitized suite's time)
  const SurfaceInput with_spike = noisy_sphere_with_spike(0.005 / std::sqrt(3.0), true);
  const Result result = skeletonize(with_spike, options);
  EXPECT_TRUE(result.smoothing_check.made);
  EXPECT_FALSE(result.smoothing_check.smoothing_kept);
  EXPECT_GT(result.smoothing_check.smoothed_cover, 0.1);
  const EvalResult fit = evaluate(with_spike, result.medial_mesh);
  EXPECT_LT(fit.surface_to_medial_max, 0.04 * fit.diagonal);

  const Result without = skeletonize(noisy_sphere_with_spike(0.005 / std::sqrt(3.0), false), options);
  EXPECT_TRUE(without.prepare.smoothed());
  EXPECT_FALSE(without.smoothing_check.made);
}

}  // namespace
}  // namespace vmas
