#pragma once
// Every option and report struct of the library, with its defaults: what a run takes (Options,
// and the options of each stage in it) and what it tells (the reports of Result). The stages
// that read and fill them are internal (src/, docs/design.md's layout); the functions of the
// public headers take and return these.
#include <array>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// ---- Preparation: what cleaning and preparation do and report ----

// What clean_surface() removed so that the shape is usable (duplicates, NaN/Inf, degenerate faces).
struct CleanReport {
  std::size_t non_finite_points = 0;  // points with a NaN coordinate (dropped)
  std::size_t missing_normals = 0;    // kept points whose normal is NaN, infinite or zero (left
                                      // NaN: preparation estimates it)
  std::size_t duplicate_points = 0;   // points at the same coordinates as an earlier one (merged)
  std::size_t degenerate_faces = 0;   // faces with a repeated or dropped vertex, or zero area
  std::size_t unused_points = 0;      // mesh vertices referenced by no face (dropped)
  std::vector<int> kept;  // index, in the surface as given, of every point kept (ascending)
  std::size_t total() const {
    return non_finite_points + duplicate_points + degenerate_faces + unused_points;
  }
};

// What makes a mesh a poor description of a solid, counted over its (undirected) edges.
struct MeshDefects {
  std::size_t boundary_edges = 0;      // on one face only: holes, an open mesh
  std::size_t non_manifold_edges = 0;  // on more than two faces
  std::size_t misoriented_edges = 0;   // its two faces run along it the same way: neighbouring
                                       // faces disagree on which side is outside
  // A mesh without any of these bounds a volume (its winding number is exactly 1 inside).
  bool closed() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0;
  }
};

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
  bool noise_from_facets = false;  // a mesh too coarse for the noise reading: what it read is
                                   // its facets, and the mesh was not smoothed
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

struct ShapeOptions {
  int k = 6;  // neighbours per point for clouds: the k-NN graph and the quadric diffusion (eq. 5)
  void validate() const;  // throws InvalidOption
};

// ---- The optimisation (Skeletonizer) ----

struct ShrinkingBallOptions {
  int max_iterations = 30;
  double tolerance = 1e-5;          // δ, relative to the bounding-box diagonal
  double initial_radius = 1.0;      // first ball radius, relative to the diagonal
  double denoise_angle_deg = 20.0;  // stop shrinking when the two contacts separate by less
                                    // than this (noise, not a medial feature); 0 disables it
  bool reject_outside = false;      // reject balls whose centre the winding number puts outside
                                    // (when the data encloses a volume); for smoothed noisy data
  double box_margin = 0.01;         // how far past the data's bounding box a ball may reach,
                                    // relative to the diagonal
  double enclosure = -1.0;          // the shape's enclosure (MedialProjector::enclosure) when
                                    // measured on a denser sampling of it; < 0: measured here
  void validate() const;            // throws InvalidOption
};

// Spheres produced when neither a count nor an error threshold is given.
constexpr int kDefaultSpheres = 100;

// Where splitting stops: a sphere count, met exactly, or an error threshold.
struct Target {
  int spheres = 0;     // spheres to produce (0: none given)
  double error = 0.0;  // instead of a count: split until every cluster's RMS error √E(C) (eq. 12)
                       // is below this fraction of the diagonal (e.g. 0.005; divided by the
                       // cluster's mean density where one is given), at most
                       // max_spheres spheres; scan noise sets a floor (0: none given)
  // The count aimed at: `spheres`, 0 when the threshold decides, kDefaultSpheres when neither
  // is given.
  int count() const { return spheres > 0 ? spheres : error > 0.0 ? 0 : kDefaultSpheres; }
};

// The Gauss–Newton refit of a cluster's sphere (paper §3.3, src/optimise/update.hpp).
struct UpdateOptions {
  int max_iterations = 10;       // Gauss–Newton steps per update
  double step_tolerance = 1e-6;  // stop when the step is shorter (relative to the diagonal)
  void validate() const;         // throws InvalidOption
};

// How many clusters one round of splitting may split (paper §3.4, src/optimise/split.hpp).
struct SplitOptions {
  double max_fraction = 0.2;  // at most this fraction of the current sphere count per round
  int max_per_round = 10;     // and at most this many (sphere-count targets only) ...
  int large_count_share = 20;  // ... or 1/this of the current count when that is more
  void validate() const;      // throws InvalidOption
};

struct SkeletonizerOptions {
  double lambda = 0.2;           // weight of the point–sphere term (eq. 8, 11)
  double final_lambda = 0.01;    // λ of the refits that end run(): spheres reach extremities
  int final_rounds = 3;          // refits after the optimisation (0: none)
  Target target;
  int max_spheres = 5000;        // hard cap when only an error threshold is given (and never
                                 // more spheres than points)
  int max_iterations = 3000;     // partition + update steps in run()
  double convergence = 2e-4;     // converged when the total error changes by less (relative)
  int split_interval = 10;       // split at least every this many steps while spheres are missing
  int settle_iterations = 3;     // steps after the last split before run() may stop
  int max_settle_iterations = 30;  // ... and after which it stops even if not converged
  int min_cluster_size = 4;        // a sphere with fewer vertices is moved to the worst vertex
                                   // of the worst cluster after a partition
  bool project = true;             // shrinking-ball correction after every update (§3.3)
  // With a sphere count: run() grows the spheres on a coarsened copy of the shape (about a
  // quarter of the vertices, at least 50 per sphere; coarsen_shape), then settles and refits
  // them on the whole shape. Steps on the coarse shape cost a fraction.
  bool coarse_start = true;
  // The medial mesh leaves out the triangles that close its cavities (MedialTopology's
  // closing_triangles): no cavity, the same pieces and loops (the medial axis of a solid encloses
  // nothing). Cluster adjacency makes every 3-clique a triangle, and closed pockets of them.
  bool open_cavities = true;
  UpdateOptions update;
  ShrinkingBallOptions shrinking_ball;
  SplitOptions split;

  void validate() const;  // throws InvalidOption

  // The range of λ and final_lambda (and of a λ changed later, EditSession::set_lambda).
  static constexpr double kMaxLambda = 1e6;
  static void check_lambda(const std::string& option, double value);  // throws InvalidOption
};

// Seconds spent in each stage: a Skeletonizer's own (partition, update, projection, split) so
// far, and vmas::skeletonize's whole run (Result::seconds).
struct Timings {
  double clean = 0.0, prepare = 0.0, shape = 0.0, partition = 0.0, update = 0.0, projection = 0.0,
         split = 0.0, refine = 0.0, connectivity = 0.0, other_starts = 0.0, smoothing_check = 0.0,
         total = 0.0;
  Timings& operator+=(const Timings& other) {
    clean += other.clean;
    prepare += other.prepare;
    shape += other.shape;
    partition += other.partition;
    update += other.update;
    projection += other.projection;
    split += other.split;
    refine += other.refine;
    connectivity += other.connectivity;
    other_starts += other.other_starts;
    smoothing_check += other.smoothing_check;
    total += other.total;
    return *this;
  }
};

struct RunSummary {
  int iterations = 0;
  int spheres = 0;
  double error = 0.0;
  bool converged = false;           // the total error settled (see convergence)
  bool hit_max_iterations = false;  // max_iterations ended the run
  bool cancelled = false;           // the progress callback returned false
  bool error_threshold_missed = false;  // an error threshold was still unmet when the run ended
                                        // (sphere cap, max_iterations, no cluster could split)
};

// ---- Measurement and the worst-case refinement ----

struct EvalOptions {
  // Random area-weighted surface samples added to the input vertices (meshes only);
  // -1: as many as there are vertices.
  int surface_samples = -1;
  // Distance between neighbouring samples on the primitives' boundaries, fraction of the
  // diagonal. The mean uses these samples; the maximum is refined 16x finer around the farthest.
  // Primitives far larger than the shape are sampled more coarsely, so that one measurement
  // never takes more than 500 000 boundary samples (about 80 MB).
  double boundary_spacing = 0.004;
  int refined_samples = 256;  // boundary samples around which the maximum is refined, per round
  // A boundary sample is hidden by another primitive only when deeper inside it than this,
  // fraction of the diagonal (touching primitives share boundary points).
  double inside_tolerance = 1e-6;
  unsigned seed = 1;  // for the random surface samples; results are deterministic per seed
  // Only the two maxima (and where they are), for callers that measure many medial meshes: the
  // means, vertex_error and the boundary samples' errors are left empty (0), and distances that
  // cannot reach a maximum are not computed exactly. The maxima are those of a full evaluation.
  bool maxima_only = false;
  // A cloud with a normal at every point stands for a surface: medial -> surface distances are
  // then to the nearest of the points' tangent discs (each reaching its point's
  // kDiscNeighbours-th nearest neighbour), not to the nearest point, so that the gaps of a sparse
  // sampling are not counted as error. Off: the nearest point, as the paper measures (vmas eval).
  bool cloud_as_discs = false;
  // Surface -> medial from at most about this many of the input's points, one per voxel
  // (src/core/subsample.hpp), when it has more (0: all of them): a smoothed mesh holds no detail finer
  // than its noise. Only with maxima_only (vertex_error needs every point).
  std::size_t max_input_points = 0;
  // Points (in the shape's frame) that close openings as a solid closes them, lids across their
  // rims, which the medial -> surface side measures to besides the shape (never from): what no
  // solid can do, come near data across an opening, is not counted; what it can, cover the data
  // and not bulge out past the rims, is. The refinement measures an open cloud so.
  std::vector<Vec3> lid_points;
  // Weights in [0, 1], one per input point (empty: all 1): each surface -> medial distance is
  // its point's times its weight, each medial -> surface distance times the weight of the point
  // nearest to the boundary sample; every figure (maxima, worst points, means, vertex_error,
  // boundary_error, ε) is then of the weighted distances. A density field's (d / d_max)²: where
  // spheres are asked to be finer their error counts more (docs/design.md, "Density"). Needs
  // surface_samples 0 (random samples have no weight). The medial side's maximum is refined
  // around its largest samples as without weights; where the weights jump it can lie more than
  // a spacing above them.
  std::vector<double> point_weights;

  void validate() const;  // throws InvalidOption
};

struct RefineOptions {
  int max_moves = 12;      // moves tried at most (0: the stage is off)
  double min_gain = 0.01;  // stop after two moves in a row that lowered the error by less than
                           // this fraction
  void validate() const;   // throws InvalidOption
};

struct RefineReport {
  int tried = 0, kept = 0;
  double error_before = 0.0, error_after = 0.0;  // measured two-sided Hausdorff, absolute
  double seconds = 0.0;
  bool cancelled = false;  // the progress callback returned false
};

struct FinishReport {
  RefineReport refine;
  double error = 0.0;      // the result's measured two-sided Hausdorff distance, absolute
  bool cancelled = false;  // the progress callback returned false
};

// Betti numbers over Z/2 of a medial mesh as a simplicial complex: its spheres, its edges and
// the edges of its triangles, its triangles (a triangle listed twice counts once, as a
// duplicate).
struct MedialTopology {
  int components = 0;  // b0
  int loops = 0;       // b1: independent cycles of edges that no triangles fill
  int cavities = 0;    // b2: closed pockets of triangles
  std::size_t duplicate_triangles = 0;
  // Triangles (indices, ascending) that each close a cavity with triangles whose slabs reach
  // out further (by the area of the centres' triangle plus the squared sum of the radii):
  // removing them all leaves no cavity, the same pieces and the same loops, and opens each
  // cavity where its wall covers least.
  std::vector<int> closing_triangles;
};

// The genus of each piece of a closed triangle mesh, from its Euler characteristic
// (V − E + F = 2 − 2g), pieces in the order of their first face. Known only for a mesh without
// boundary, non-manifold or misoriented edges whose characteristic is even and at most 2 per
// piece; otherwise `why` says why not.
struct SurfaceGenus {
  bool known = false;
  std::vector<int> genus;  // per piece
  std::string why;         // when not known
  // Handles of all pieces: the loops of their medial axis (0 when not known).
  int handles() const { return std::accumulate(genus.begin(), genus.end(), 0); }
};

// ---- A whole run (vmas::skeletonize) ----

// Every option of `vmas skeletonize`, with its defaults.
constexpr int kMaxStarts = 8;

struct Options {
  int threads = 0;          // OpenMP threads of this call (0: OpenMP's default, all cores)
  int starts = 2;           // optimisations, each in its own turn of the working frame
                            // (turn_working_frame), at most kMaxStarts; the one with the least
                            // measured error whose skeleton has no more pieces than the input is
                            // the result. The optimisation is a local search
                            // that rounding sends elsewhere: two starts make a poor result rarer
                            // (1: less time)
  PrepareOptions prepare;   // denoising (auto), outliers, normal estimation and orientation
  ShapeOptions shape;       // k of a cloud's neighbour graph
  SkeletonizerOptions run;  // the target (run.target: spheres or error), λ, final refits,
                            // convergence, shrinking balls, ...
  RefineOptions refine;     // worst-case refinement after the run (max_moves 0: off)
  // A closed mesh of known genus g: the skeleton's loops are brought to g. Extra ones (rings of
  // spheres around a tube) are filled with triangles between their spheres, the shortest first;
  // a missing one (a handle's loop filled by a triangle whose three clusters meet nowhere on the
  // surface, but pairwise around the handle) is opened by leaving such triangles out
  // (Result::loops_filled, loops_opened). No sphere is added or moved. False: the loops are
  // kept as cluster adjacency makes them.
  bool loops_to_genus = true;
  // Throws InvalidOption naming the option; option() gives its CLI name.
  void validate() const;
};

// Something about the input or the result the caller should know; the result is still usable.
struct Warning {
  // A stable identifier, for programs: "open-surface", "open-mesh", "misoriented-faces",
  // "inward-normals", "normals-reoriented" (a cloud's normals of arbitrary sign, oriented),
  // "split-skeleton", "topology-mismatch" (loops other than the input's genus, or cavities),
  // "large-error" (measured ε above 5 % of the diagonal),
  // "target-not-reached" (an error threshold stopped at the sphere cap).
  std::string code;
  std::string message;  // one line, for people
};


// When the noise of a cloud was smoothed and the skeleton came out far from the data
// (large-error), or a part of the data lies far from it (the smoothing took a thin part away),
// the points were skeletonized a second time as they are (--denoise off), and both skeletons
// measured against them: the smoothed one is the result unless the other reaches less far past
// them by more than the noise, or comes nearer their farthest point by far more (lengths:
// fraction of the diagonal).
struct SmoothingCheck {
  bool made = false;
  bool smoothing_kept = true;     // false: the result is that of the unsmoothed points
  double smoothed_reach = 0.0;    // medial -> data maximum of the smoothed points' skeleton
  double unsmoothed_reach = 0.0;  // and of the unsmoothed points' skeleton
  double smoothed_cover = 0.0;    // data -> medial maximum of the smoothed points' skeleton
  double unsmoothed_cover = 0.0;  // and of the unsmoothed points' skeleton
};

// Spheres that a closed input shows to be no medial balls (invalid_spheres in src/pipeline/validity.hpp):
// counted only when the input encloses a volume (a mesh without defects, or a cloud whose
// winding number reads closed and that has no holes).
struct InvalidSpheres {
  bool checked = false;        // the input is closed, so the counts below mean something
  std::size_t outside = 0;     // centres whose winding number is at most ½
  std::size_t radius_off = 0;  // radii further than 1 % of the diagonal from the centre's
                               // distance to the surface
};

}  // namespace vmas

#pragma GCC visibility pop
