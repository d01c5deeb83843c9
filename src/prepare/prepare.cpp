#include "prepare/prepare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>

#include "core/cloud_graph.hpp"
#include "core/density_mean.hpp"
#include "core/principal_axes.hpp"
#include "core/stopwatch.hpp"
#include "core/subsample.hpp"
#include "core/validate_member.hpp"
#include "prepare/fringe.hpp"
#include "prepare/holes.hpp"
#include "prepare/mesh_sampling.hpp"
#include "prepare/noise.hpp"
#include "prepare/normals.hpp"
#include "prepare/outliers.hpp"
#include "prepare/smoothing.hpp"
#include "prepare/stray_clusters.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"

namespace vmas {

namespace {

template <typename T>
void keep_only(std::vector<T>& values, const std::vector<int>& kept) {
  if (values.empty()) return;
  std::vector<T> selected;
  selected.reserve(kept.size());
  for (int i : kept) selected.push_back(values[i]);
  values = std::move(selected);
}

// Points needed for a noise estimate; smaller clouds are taken as they are.
constexpr std::size_t kMinPointsForNoise = kFewestNoiseNeighbours;
// A deviation from the smoothed surface more than this many times the noise sets the smoothing's
// scale, at most kMaxScaleInNoises times the noise; read up to kDeviationReadings times when the
// noise may read low (smooth_noisy_cloud).
constexpr double kScaleRaise = 1.1, kMaxScaleInNoises = 1.5;
constexpr int kDeviationReadings = 2;
// Fewer points than this would starve the optimisation: a budget below is a mistake.
constexpr int kMinMaxPoints = 1000;
// Points at which the smoothing's deviation is measured: a median over a few thousand is stable
// to a few percent, and fitting the surface at all of them cost as much as the smoothing itself.
constexpr int kDeviationSamples = 4000;
// Pairs of Taubin passes for a noisy mesh (smooth_mesh).
constexpr int kMeshSmoothingSteps = 40;
// A mesh's noise is read from fits to 16 or more of its vertices; where they lie more than this
// fraction of the diagonal apart, such a fit spans a bend of the shape and a clean low-poly mesh's
// facets read as noise (CGAL's 231-vertex double torus: 1.9 %; smoothed, it kept 2.25 % and its
// skeleton fell apart). The noisiest meshes of Table 2 are at most 1 % apart.
constexpr double kMeshSpacingForNoise = 0.02;
// A smoothed cloud's points are needed about this many noises apart (the MLS fits sit on a grid
// of 4 / 6 of the smoothing's scale, which is at least the noise), and at least this many per
// sphere (a gear's 230 spheres on 2 600 points came out worse than without smoothing).
constexpr double kSmoothedSpacingInNoises = 0.7;
constexpr std::size_t kMinPointsPerSphere = 50;
// Least reach of balls past the bounding box of open data (relative to the diagonal).
constexpr double kMinOpenMargin = 1e-3;
// A file's normals whose neighbours on one sheet disagree this often have arbitrary signs: half
// of random signs disagree, oriented normals almost never.
constexpr double kMixedNormalSigns = 0.1;
// Upper end of the shrinking-ball tolerance (ShrinkingBallOptions::validate takes < 0.1).
constexpr double kMaxBallTolerance = 0.05;

// Coordinates are scaled by a power of two when the longest side of the bounding box is
// outside [1 / kSizeRange, kSizeRange], so that no stage loses precision to their magnitude.
constexpr double kSizeRange = 1e3;
// A later start's working frame is the first one turned by this angle per start about its
// diagonal (turn_working_frame): any angle does that aligns no grid with the first.
constexpr double kTurnRadians = 0.3;

// The working frame of `points` (see prepare_surface). The principal axes of the points, largest
// spread first, each pointing to the side with the larger third moment (right-handed: the third
// is the cross product of the first two): functions of the shape alone, so a rotated, moved or
// scaled copy of the data gets the same working coordinates up to rounding and scale.
Frame working_frame(const std::vector<Vec3>& points) {
  Frame frame;
  if (points.empty()) return frame;
  std::vector<int> all(points.size());
  std::iota(all.begin(), all.end(), 0);
  const internal::PrincipalAxes fit = internal::principal_axes(points, all);
  frame.origin = fit.centroid;
  if (fit.valid) {
    Eigen::Matrix3d axes;
    for (int k = 0; k < 3; ++k) axes.col(k) = fit.axes.col(2 - k);
    for (int k = 0; k < 2; ++k) {
      double third_moment = 0.0;
      for (const Vec3& p : points) third_moment += std::pow(axes.col(k).dot(p - frame.origin), 3);
      if (third_moment < 0.0) axes.col(k) = -axes.col(k);
    }
    axes.col(2) = axes.col(0).cross(axes.col(1));
    frame.axes = axes;
  }
  // Relative figures (options, reports) are of the input's bounding-box diagonal: the working
  // box keeps it. Sides relative to the longest one: a diagonal of coordinates ~1e-300 would
  // underflow.
  const Vec3 input_sides = bounding_box(points).sizes();
  Box turned;
  for (const Vec3& p : points) turned.extend(Vec3(frame.axes.transpose() * (p - frame.origin)));
  const Vec3 turned_sides = turned.sizes();
  const double unit = turned_sides.maxCoeff();
  if (!(unit > 0.0)) return frame;
  frame.scale = (turned_sides / unit).norm() / (input_sides / unit).norm();
  const double size = turned_sides.maxCoeff() / frame.scale;
  if (size > kSizeRange || size < 1.0 / kSizeRange)
    frame.scale *= std::ldexp(1.0, std::ilogb(size));
  return frame;
}

}  // namespace

Vec3 Frame::to_working(const Vec3& p) const { return axes.transpose() * (p - origin) / scale; }

MedialMesh Frame::to_input(MedialMesh mesh) const {
  for (Sphere& s : mesh.spheres) {
    s.center = to_input(s.center);
    s.radius *= scale;
  }
  return mesh;
}

void PrepareOptions::validate() const {
  if (max_points != 0 && max_points < kMinMaxPoints)
    throw InvalidOption("max_points", "must be 0 (every point) or at least " +
                                          std::to_string(kMinMaxPoints) + " (got " +
                                          std::to_string(max_points) + ")");
  if (denoise == Denoise::Fixed && !(noise_sigma >= 0.0 && noise_sigma < 0.5))
    throw InvalidOption("noise_sigma",
                        "deviation must be in [0, 0.5) of the bounding-box diagonal (got " +
                            std::to_string(noise_sigma) + ")");
  internal::validate_member("normals", normals);
  internal::validate_member("noise", noise);
}

namespace {

// Keeps the point of every cell of `thin` (a subsample of surface.points): it stands for the input
// points its cell's points stood for.
void keep_cells(const Subsample& thin, SurfaceInput& surface, PrepareReport& report) {
  for (int& p : report.stand_in)
    if (p >= 0) p = thin.representative[p];
  for (Hole& hole : report.holes) {
    for (int& p : hole.rim) p = thin.representative[p];
    std::sort(hole.rim.begin(), hole.rim.end());
    hole.rim.erase(std::unique(hole.rim.begin(), hole.rim.end()), hole.rim.end());
  }
  keep_only(report.kept, thin.kept);
  keep_only(surface.points, thin.kept);
  keep_only(surface.normals, thin.kept);
  // A cell's point stands for the points thinned away: it carries their mean density.
  if (!surface.density.empty())
    surface.density = internal::mean_density_by_group(surface.density, thin.representative,
                                                      thin.kept.size(), 0.0);
}

// Every later stage costs at least linear time in the points; a big cloud's detail below a few
// hundred points per sphere changes nothing but the time.
void thin_big_cloud(SurfaceInput& surface, PrepareReport& report, std::size_t budget) {
  if (surface.is_mesh() || budget == 0 || surface.points.size() <= budget) return;
  const Subsample thin = subsample(surface.points, budget);
  report.thinned_from = surface.points.size();
  report.voxel = thin.leaf;
  keep_cells(thin, surface, report);
}

// Keeps the points of `surface` at `kept` (ascending) and counts the others as outliers: the input
// points they stood for get no label.
void drop_all_but(const std::vector<int>& kept, SurfaceInput& surface, PrepareReport& report) {
  report.outliers += surface.points.size() - kept.size();
  std::vector<int> position(surface.points.size(), -1);
  for (std::size_t j = 0; j < kept.size(); ++j) position[kept[j]] = static_cast<int>(j);
  for (int& p : report.stand_in)
    if (p >= 0) p = position[p];
  keep_only(report.kept, kept);
  keep_only(surface.points, kept);
  keep_only(surface.normals, kept);
  keep_only(surface.density, kept);
}

// Stray points far from the surface (scanner artefacts, registration leftovers) would each stop
// shrinking balls and pull clusters; a mesh's vertices are never strays. Returns whether the
// noise was measured on the way (report.noise).
bool drop_outliers(SurfaceInput& surface, PrepareReport& report, const PrepareOptions& options) {
  if (surface.is_mesh() || options.denoise == PrepareOptions::Denoise::Off ||
      !options.remove_outliers)
    return false;
  bool noise_measured = false;
  std::vector<int> inliers = inlier_indices(surface.points, options.noise);
  // The strays go with the tails of a scan's noise, which its smoothing is better without
  // (bear, dove, chair at σ = 0.5-1 %: ε 0.3-13 points lower); a clean sampling keeps its
  // sparse parts. The noise is measured without the strays either way.
  if (options.denoise == PrepareOptions::Denoise::Auto && inliers.size() >= kMinPointsForNoise) {
    std::vector<Vec3> strict;
    strict.reserve(inliers.size());
    for (int i : inliers) strict.push_back(surface.points[i]);
    report.noise = estimate_noise(strict);
    noise_measured = true;
    if (!is_noisy(report.noise, options.noise))
      inliers = with_sparse_parts(surface.points, inliers, options.noise);
  }
  drop_all_but(inliers, surface, report);
  return noise_measured;
}

// Groups of points apart from the object that the outlier filter left (each point of a group has
// close neighbours: one another), on any cloud, clean or noisy: each is one sphere's worth of
// points that the optimisation would reach out to. Judged on the cloud as thinned, each point
// weighing the input points it stands for; `noise`: the noise if measured (else measured when
// needed). Returns the points' kJoiningNeighbours neighbourhoods when no point went (none when
// it did not look, or did remove points).
std::optional<internal::Neighbourhoods> drop_stray_clusters(SurfaceInput& surface,
                                                            PrepareReport& report,
                                                            const PrepareOptions& options,
                                                            const NoiseEstimate* noise) {
  if (surface.is_mesh() || !options.remove_stray_clusters) return std::nullopt;
  std::vector<std::size_t> weights(surface.points.size(), 0);
  for (int p : report.stand_in)
    if (p >= 0) ++weights[p];
  internal::Neighbourhoods rows =
      internal::k_nearest_all(surface.points, internal::kJoiningNeighbours);
  const StrayClusterSplit split =
      without_stray_clusters(surface.points, rows, weights, noise ? noise->sigma : -1.0);
  if (split.clusters == 0) return rows;
  std::vector<char> kept(surface.points.size(), 0);
  for (int p : split.kept) kept[p] = 1;
  for (std::size_t i = 0; i < report.stand_in.size(); ++i)
    if (report.stand_in[i] >= 0 && !kept[report.stand_in[i]])
      report.stray_points.push_back(static_cast<int>(i));
  report.stray_clusters = split.clusters;
  drop_all_but(split.kept, surface, report);
  return std::nullopt;
}

// Whether the points call for smoothing: the noise measured (unless already) or given.
bool is_noisy_input(const SurfaceInput& surface, PrepareReport& report,
                    const PrepareOptions& options, bool noise_measured) {
  if (options.denoise == PrepareOptions::Denoise::Auto &&
      surface.points.size() >= kMinPointsForNoise) {
    if (!noise_measured) report.noise = estimate_noise(surface.points);
    report.noise_from_facets =
        surface.is_mesh() && report.noise.spacing > kMeshSpacingForNoise * report.diagonal;
    return !report.noise_from_facets && is_noisy(report.noise, options.noise);
  }
  if (options.denoise == PrepareOptions::Denoise::Fixed) {
    if (surface.points.size() >= kMinPointsForNoise)
      report.noise.spacing = estimate_noise(surface.points).spacing;
    report.noise.sigma = options.noise_sigma * report.diagonal;
    return report.noise.sigma > 0.0;
  }
  return false;
}

// A noisy mesh stays a mesh: its faces say what the surface connects, whatever the vertices'
// noise (and a closed one stays closed).
void smooth_noisy_mesh(SurfaceInput& surface, PrepareReport& report,
                       const PrepareOptions& options) {
  report.mesh_smoothing_steps = kMeshSmoothingSteps;
  const double moved = smooth_mesh(surface.points, surface.faces, report.mesh_smoothing_steps);
  // Local fits read strong noise low; the smoothing's displacement does not.
  if (options.denoise == PrepareOptions::Denoise::Auto)
    report.noise.sigma = std::max(report.noise.sigma, moved);
  report.residual_noise = estimate_noise(surface.points).sigma;
}

// Stages of smooth_noisy_cloud that prepare_surface reports (each a call of `stage_done`).
constexpr int kSmoothingStages = 2;

// MLS smoothing of a noisy cloud; returns the smoothed surface's (unoriented) normals.
std::vector<Vec3> smooth_noisy_cloud(SurfaceInput& surface, PrepareReport& report,
                                     const PrepareOptions& options,
                                     const std::function<void()>& stage_done) {
  // The support must hold enough samples for a quadric fit even when the noise is far below
  // the spacing.
  const auto radius_for = [&](double sigma) {
    return std::max(options.noise.mls_radius_in_sigmas * sigma, 3.0 * report.noise.spacing);
  };
  // The scale of the smoothing: the noise, or the deviation by which smoothing at the noise's
  // scale moves the points when that is higher. Fits in the smallest neighbourhoods may lie
  // inside the noise (the radius test passes on a residual read low): then the deviation is the
  // noise too, and since a support sized by a noise read low lies partly inside the noise as
  // well, the deviation is read again at its own scale (chair and santa at σ = 1 %: 0.71 and
  // 0.70 of the noise after one reading, 0.86 and 0.78 after two). Fits in larger ones passed it
  // on a residual that reaches past the noise, while the deviation also holds the geometry finer
  // than the smoothing's support (a gear's teeth, thin parts): the noise stays as read, and the
  // smoothing at that scale, which measured no worse than at the noise's (docs/noise.md, step 3).
  double scale = report.noise.sigma;
  if (options.denoise == PrepareOptions::Denoise::Auto) {
    const bool read_low = report.noise.neighbours == kFewestNoiseNeighbours;
    // Thin parts that the smoothing folds onto one sheet overstate it: bounded.
    const double most = kMaxScaleInNoises * report.noise.sigma;
    for (int reading = 0; reading < (read_low ? kDeviationReadings : 1); ++reading) {
      const double moved =
          std::min(mls_deviation(surface.points, radius_for(scale), kDeviationSamples), most);
      if (!(moved > kScaleRaise * scale)) break;
      scale = moved;
      if (read_low) report.noise.sigma = moved;
    }
  }
  stage_done();
  report.mls_radius = radius_for(scale);
  std::vector<Vec3> raw = surface.points;
  std::vector<Vec3> normals = smooth_mls(surface.points, report.mls_radius);
  stage_done();
  const std::vector<int> supported = supported_by_noise(
      surface.points, raw, std::max(scale, 2.0 * report.noise.spacing));
  drop_all_but(supported, surface, report);
  keep_only(normals, supported);
  keep_only(raw, supported);
  restore_smoothing_bias(surface.points, normals, raw, report.mls_radius);
  report.residual_noise = estimate_noise(surface.points).sigma;
  return normals;
}

// A cloud's normals: the smoothed surface's when it was smoothed, estimated when the file has
// none (or they are not wanted), else the file's signs on the normals of the surface (smoothed or
// fitted to the points), and, when asked, re-oriented.
void cloud_normals(SurfaceInput& surface, PrepareReport& report, const PrepareOptions& options,
                   std::vector<Vec3> smoothed_normals,
                   const std::optional<internal::Neighbourhoods>& neighbours) {
  const bool estimate = !surface.has_normals() || options.estimate_normals;
  if (!smoothed_normals.empty() && estimate) {
    // The MLS normals are those of the smoothed surface at the noise's scale: better than a
    // fresh fit to a few neighbours; only their signs are missing.
    surface.normals = std::move(smoothed_normals);
    orient_smoothed_normals(surface.points, surface.normals, options.normals.k);
    report.normals_estimated = true;
  } else if (estimate) {
    // The stray clusters' neighbourhoods serve when the points are still theirs and k agrees.
    surface.normals = neighbours && options.normals.k == internal::kJoiningNeighbours
                          ? estimate_normals(surface.points, options.normals, *neighbours)
                          : estimate_normals(surface.points, options.normals);
    report.normals_estimated = true;
  } else {
    refit_given_normals(surface.points, surface.normals, options.normals.k,
                        std::move(smoothed_normals));
    // Normals estimated elsewhere often come with arbitrary signs (PCA's): oriented then, and said.
    // (Not on a smoothed cloud: its thin parts' sheets come close enough to read as one.)
    if (!options.orient_normals && !report.smoothed())
      report.normals_disagreement = sign_disagreement(surface.points, surface.normals);
    if (options.orient_normals || report.normals_disagreement > kMixedNormalSigns) {
      orient_normals(surface.points, surface.normals, options.normals.k);
      report.normals_oriented = true;
    }
  }
}

}  // namespace

PrepareReport prepare_surface(SurfaceInput& surface, const PrepareOptions& options,
                              const std::function<bool(int)>& keep_going) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  int stage = 0;
  // `count`: stages skipped included.
  const auto stage_done = [&](int count = 1) {
    stage += count;
    if (keep_going && !keep_going(stage)) throw Cancelled();
  };
  PrepareReport report;
  report.kept.resize(surface.points.size());
  std::iota(report.kept.begin(), report.kept.end(), 0);
  report.stand_in = report.kept;
  if (!surface.density.empty()) {
    const auto [low, high] = std::minmax_element(surface.density.begin(), surface.density.end());
    report.density_given = true;
    report.density_low = *low;
    report.density_high = *high;
  }
  report.frame = working_frame(surface.points);
  for (Vec3& p : surface.points) p = report.frame.to_working(p);
  for (Vec3& n : surface.normals) n = report.frame.axes.transpose() * n;
  stage_done();
  thin_big_cloud(surface, report, static_cast<std::size_t>(options.max_points));
  stage_done();
  const bool noise_measured = drop_outliers(surface, report, options);
  stage_done();
  std::optional<internal::Neighbourhoods> neighbours =
      drop_stray_clusters(surface, report, options, noise_measured ? &report.noise : nullptr);
  stage_done();
  report.diagonal = diagonal_of(bounding_box(surface.points));
  const bool noisy = is_noisy_input(surface, report, options, noise_measured);
  std::vector<Vec3> smoothed_normals;
  if (!noisy) {
    report.residual_noise = report.noise.sigma;
    stage_done(kSmoothingStages);
  } else if (surface.is_mesh()) {
    smooth_noisy_mesh(surface, report, options);
    stage_done(kSmoothingStages);
  } else {
    neighbours.reset();  // the smoothing moves the points
    smoothed_normals = smooth_noisy_cloud(surface, report, options, [&] { stage_done(); });
  }
  stage_done();
  // Only a clean mesh: a smoothed one's thin faces are the noise's, not an exporter's.
  if (surface.is_mesh() && !report.smoothed() && options.sample_coarse_meshes) {
    const MeshSampling sampling = sample_coarse_mesh(surface);
    report.mesh_sampled_from = sampling.vertices_before;
    if (sampling.vertices_before > 0) report.mesh_sampled_to = surface.points.size();
    report.mesh_edge_limit = sampling.edge_limit;
  }
  // A mesh's normals, areas and quadrics come from its faces, its holes are its boundary edges
  // (MeshDefects).
  if (!surface.is_mesh()) {
    cloud_normals(surface, report, options, std::move(smoothed_normals), neighbours);
    report.holes = find_holes(surface.points, surface.normals, report.smoothed());
  }
  stage_done();
  report.seconds = internal::seconds_since(start);
  return report;
}

std::size_t smoothed_points_needed(const SurfaceInput& surface, const PrepareReport& report,
                                   int spheres) {
  const std::size_t count = surface.points.size();
  const double spacing = kSmoothedSpacingInNoises * report.noise.sigma;
  if (!report.smoothed() || spheres <= 0 || !(spacing > report.noise.spacing))
    return count;
  const double share = std::pow(report.noise.spacing / spacing, 2);
  return std::min(count, std::max({static_cast<std::size_t>(share * static_cast<double>(count)),
                                   kMinPointsPerSphere * static_cast<std::size_t>(spheres),
                                   static_cast<std::size_t>(kMinMaxPoints)}));
}

void thin_smoothed_cloud(SurfaceInput& surface, PrepareReport& report, std::size_t budget) {
  if (surface.is_mesh() || surface.points.size() <= budget) return;
  const Subsample thin = subsample(surface.points, budget);
  report.smoothed_thinned_from = surface.points.size();
  report.smoothed_voxel = thin.leaf;
  keep_cells(thin, surface, report);
}

void turn_working_frame(PrepareReport& report, SurfaceInput& surface, int turn) {
  const Eigen::Matrix3d turning =
      Eigen::AngleAxisd(kTurnRadians * turn, Vec3::Ones().normalized()).toRotationMatrix();
  report.frame.axes = report.frame.axes * turning;
  for (Vec3& p : surface.points) p = turning.transpose() * p;
  for (Vec3& n : surface.normals) n = turning.transpose() * n;
}

void adapt_shrinking_ball(const PrepareReport& report, ShrinkingBallOptions& options) {
  if (!(report.diagonal > 0.0)) return;
  // Through a hole a ball would grow until the bounding box stops it; the data says nothing of
  // the surface beyond its extent but the noise.
  if (!report.holes.empty())
    options.box_margin = std::min(
        options.box_margin, std::max(2.0 * report.residual_noise / report.diagonal, kMinOpenMargin));
  if (!report.smoothed()) return;
  options.tolerance = std::clamp(2.0 * report.residual_noise / report.diagonal, options.tolerance,
                                 kMaxBallTolerance);
  options.reject_outside = true;
}

}  // namespace vmas
