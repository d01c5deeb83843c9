#pragma once
// Turns a cleaned input into what the skeletonizer needs: outliers removed, scan noise measured
// and smoothed away, normals estimated and oriented. What a front end would otherwise have to
// repeat; the CLI is one caller.
#include <functional>
#include <string>
#include <vector>

#include "vmas/projection.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// Scan noise as estimate_noise (src/prepare/noise.hpp) reads it.
struct NoiseEstimate {
  double sigma = 0.0;    // standard deviation of the positions across the surface (absolute)
  double spacing = 0.0;  // median distance from a point to its nearest neighbour (absolute)
  int neighbours = 0;    // neighbourhood size (k) the estimate was read at
};

// Outlier removal and smoothing (src/prepare/outliers.hpp, smoothing.hpp, fringe.hpp).
struct DenoiseOptions {
  // Noise at or below this fraction of the spacing is left alone: clean samples, meshes whose
  // fine relief reads as noise, and scans whose mild noise does not disturb the shrinking balls
  // (smoothing them would blur what matters more, such as registration seams).
  double clean_fraction_of_spacing = 0.35;
  double mls_radius_in_sigmas = 4.0;  // MLS support radius, in smoothing scales (noise.md, step 3)
  int outlier_k = 16;                 // statistical outlier removal: neighbours per point ...
  double outlier_deviations = 3.0;    // ... and the mean distance beyond mean + this × std
  void validate() const;              // throws InvalidOption
};

// Normal estimation and orientation of clouds (src/prepare/normals.hpp).
struct NormalOptions {
  int k = 16;             // neighbours used for the PCA plane fit and for the orientation graph
  void validate() const;  // throws InvalidOption
};

// A hole of a cloud: a rim where the sampling stops (src/prepare/holes.hpp).
struct Hole {
  double width = 0.0;    // diagonal of the rim's bounding box (absolute)
  std::vector<int> rim;  // indices of the points found on its rim, ascending
};

// Clouds with more points are thinned to about this many (coarse-to-fine, src/core/subsample.hpp).
constexpr int kDefaultMaxPoints = 100000;

struct PrepareOptions {
  enum class Denoise { Auto, Off, Fixed };
  int max_points = kDefaultMaxPoints;  // clouds only; 0: every point takes part
  Denoise denoise = Denoise::Auto;  // Auto: measure the noise; Fixed: take `noise_sigma`
  double noise_sigma = 0.0;         // with Fixed: noise deviation, fraction of the diagonal
  bool remove_outliers = true;      // clouds, unless denoise is Off
  bool remove_stray_clusters = true;  // clouds, whatever denoise says (src/prepare/stray_clusters.hpp)
  bool sample_coarse_meshes = true;   // clean meshes: a coarse one's faces sampled
                                      // (src/prepare/mesh_sampling.hpp)
  bool estimate_normals = false;    // clouds: estimate even when the file has normals
  bool orient_normals = false;      // clouds: re-orient the surface's normals (signs not trusted)
  NormalOptions normals;
  DenoiseOptions noise;
  void validate() const;  // throws InvalidOption
};

// Where the prepared coordinates lie in the input's: working = axesᵀ (input − origin) / scale.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: the working axes, in the input
  double scale = 1.0;
  Vec3 to_working(const Vec3& p) const;
  Vec3 to_input(const Vec3& p) const { return origin + scale * (axes * p); }
  Vec3 direction_to_input(const Vec3& d) const { return axes * d; }
  // A medial mesh computed from prepared points, back in the input's coordinates.
  MedialMesh to_input(MedialMesh mesh) const;
};

struct PrepareReport {
  Frame frame;                  // the working frame of the prepared points
  std::vector<int> kept;        // input index of every prepared point, ascending (a sampled
                                // mesh's new vertices, which follow, have none)
  std::vector<int> stand_in;    // for every input point: the prepared point that stands for it
                                // (itself, or its voxel's point when thinned; −1: dropped)
  std::size_t thinned_from = 0;  // points before thinning (0: not thinned)
  double voxel = 0.0;            // edge of the thinning grid (absolute, prepared coordinates)
  std::size_t smoothed_thinned_from = 0;  // smoothed clouds: points before thin_smoothed_cloud
                                          // (0: not thinned)
  double smoothed_voxel = 0.0;            // edge of that thinning's grid (absolute)
  bool density_given = false;             // the surface had a density (SurfaceInput::density): its
  double density_low = 0.0, density_high = 0.0;  // least and largest value
  std::size_t outliers = 0;     // points dropped as strays or as the noise's fringe
  std::size_t stray_clusters = 0;  // groups of points apart from the object, removed (their
  std::vector<int> stray_points;   // input points, ascending, are among the outliers)
  NoiseEstimate noise;          // as measured (or given), before smoothing
  double diagonal = 0.0;        // bounding-box diagonal of the prepared points
  double mls_radius = 0.0;      // clouds: support of the MLS smoothing (0: not smoothed)
  int mesh_smoothing_steps = 0;  // meshes: Taubin steps along the faces (0: not smoothed)
  std::size_t mesh_sampled_from = 0;  // a coarse mesh: its vertices before and after its faces
  std::size_t mesh_sampled_to = 0;    // were sampled (0: not sampled; the new vertices follow
  double mesh_edge_limit = 0.0;       // the old ones), and the length of edges it split (absolute)
  double residual_noise = 0.0;  // noise deviation left after smoothing (absolute)
  bool normals_estimated = false, normals_oriented = false;
  std::size_t normals_turned = 0;  // estimated normals turned over by turn_inside_out_normals
  double normals_disagreement = 0.0;  // a file's normals: the share of neighbours on one sheet
                                      // pointing opposite ways; above 10 % they were oriented
  std::vector<Hole> holes;      // clouds: holes of the prepared points, widest first
  double seconds = 0.0;
  bool smoothed() const { return mls_radius > 0.0 || mesh_smoothing_steps > 0; }
};

// Prepares `surface` in place (see above). The points are first moved to a working frame
// (report.frame; map results back with Frame::to_input): their centroid at the origin, their
// principal axes along x, y, z, the bounding-box diagonal kept, a power-of-two scale for data of
// extreme size. So no stage loses precision to an offset (georeferenced scans), and the skeleton
// does not depend on how the data was placed: the same shape rotated, moved or scaled gives the
// same skeleton, rotated, moved and scaled with it. A clean mesh is left as it is unless it is too
// coarse for the method (its faces are then sampled: sample_coarse_mesh); a noisy one has
// its vertices smoothed along its faces (smooth_mesh) and stays a mesh. Throws InvalidInput when
// too few points remain.
// `keep_going` (optional) is called between stages, so that a long preparation can be stopped
// (vmas::Cancelled is thrown when it returns false) and followed: its argument is the stages
// done so far, of kPrepareStages.
constexpr int kPrepareStages = 8;
PrepareReport prepare_surface(SurfaceInput& surface, const PrepareOptions& options,
                              const std::function<bool(int)>& keep_going = {});

// How many of a prepared surface's points a run of `spheres` spheres needs: a smoothed surface
// holds no detail finer than its noise, and its points about 0.7 noises apart are enough, but no
// fewer than 50 per sphere; every point otherwise (a clean surface, or spheres 0: not known). A
// smoothed cloud is thinned to them (thin_smoothed_cloud); a smoothed mesh keeps its vertices,
// and the refinement measures on that many (EvalOptions::max_input_points).
std::size_t smoothed_points_needed(const SurfaceInput& surface, const PrepareReport& report,
                                   int spheres);

// Thins the prepared `surface` (points and normals) to about `budget` points, one per voxel
// (src/core/subsample.hpp), when it has more; the report's stand_in and kept follow.
void thin_smoothed_cloud(SurfaceInput& surface, PrepareReport& report, std::size_t budget);

// The orientation of a smoothed cloud's estimated normals turns over only large regions (its
// tree and its views); the small patches it leaves inside out, where noise near thin parts
// misled the tree, are turned over here by the winding number (MedialProjector::inside_out).
// `shape`: built from `surface` (build_shape), to be built again when any normal was turned
// (its quadrics follow the normals). Returns how many, also in report.normals_turned; any other
// surface, and one with holes, is left as it is (0).
std::size_t turn_inside_out_normals(SurfaceInput& surface, PrepareReport& report,
                                    const Shape& shape);

// Density (SurfaceInput::density; docs/design.md, "Density"). Throws InvalidInput naming the
// first problem when `density` is not one finite value >= 0 per point of `points`, or all 0.
void check_density(const std::vector<double>& density, std::size_t points);

// A density for the points of `surface` (as stored, in its coordinates) by a rule:
//   "curvature": 1 where the surface is flattest, rising with the surface variation of a point's
//     16 nearest neighbours (the least of their spread's eigenvalues over the sum) to 4 at the
//     5 % most curved points: sharp edges and small features of a part get finer;
//   "distance-to:X,Y,Z,R[,D]": D (4 unless given) within R of the point (X, Y, Z), 1 elsewhere.
// Points with a NaN coordinate get 1. Throws InvalidOption ("density") for another rule.
std::vector<double> density_by_rule(const SurfaceInput& surface, const std::string& rule);
// Whether `text` names one of those rules (well formed or not), rather than a file.
bool is_density_rule(const std::string& text);

// Turns the working frame of `report` and the prepared `surface` in it `turn` times by a fixed
// angle about the frame's diagonal: the same points, in coordinates that round differently (and
// another start of the optimisation, Options::starts).
void turn_working_frame(PrepareReport& report, SurfaceInput& surface, int turn);

// Shrinking-ball settings suited to what preparation left. Smoothed (noisy) data: samples that
// scatter around the smoothed surface by the residual noise must not shrink a ball, and a ball
// whose centre is outside the shape is rejected (noise flips normals near thin parts). Data
// with holes: balls reach past its bounding box by twice the residual noise at most (0.1 % of
// the diagonal at least). Clean closed data keeps `options` as they are.
void adapt_shrinking_ball(const PrepareReport& report, ShrinkingBallOptions& options);

}  // namespace vmas

#pragma GCC visibility pop
