#pragma once
// The optimisation state and loop of variational medial axis sampling (paper §3): spheres,
// the partition of the shape among them, per-cluster errors and frozen flags, and the run
// schedule (advance). vmas::skeletonize runs it whole (run), EditSession turn by turn while
// spheres are added, removed or frozen between turns.
//
// Sphere ids are indices into spheres(); removing a sphere shifts the later ids down by one.
// Keys name spheres for their life: a sphere keeps its key whatever is added or removed.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "vmas/projection.hpp"
#include "vmas/shape.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

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

struct Progress {
  // The phases in the order a run goes through them; `fraction` rises from 0 to 1 once in each
  // (a phase may be skipped, and may end before its fraction reaches 1).
  // Preparing: vmas::skeletonize's stages before the run (round: stages done of rounds).
  // Optimising: after every step while spheres are still added (fraction: spheres of
  //   target_spheres; with an error threshold, how far the worst cluster's error has come down
  //   to it, on a log scale).
  // Settling: after every step once no sphere is missing (round: steps since the last split,
  //   of at most rounds; 1 when the spheres have settled).
  // FinalRefit: after every final refit (round of rounds).
  // Refining: before every move of the worst-case refinement (vmas/refine.hpp; round of at most
  //   rounds; error: the measured two-sided error / diagonal), and once when it ends.
  // OtherStarts: vmas::skeletonize's starts after the first (round: this start, of rounds),
  //   while they run one after the other or while the first waits for them.
  // SmoothingCheck: vmas::skeletonize's second pass over the points as they are (docs/noise.md).
  enum class Phase {
    Preparing,
    Optimising,
    Settling,
    FinalRefit,
    Refining,
    OtherStarts,
    SmoothingCheck
  };
  Phase phase = Phase::Optimising;
  int iteration = 0;          // steps so far
  int spheres = 0;            // spheres now
  int target_spheres = 0;     // the count asked for (0: an error threshold)
  double error = 0.0;         // total error Σ E_v / A(shape)
  int round = 0, rounds = 0;  // as the phase says
  double fraction = 0.0;      // of the phase done, in [0, 1]
};

// Called from the thread that runs the optimisation; returning false stops it there.
using ProgressCallback = std::function<bool(const Progress&)>;

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

// Everything a run's result depends on: restore() brings a skeletonizer back to it exactly.
struct SkeletonizerState {
  std::vector<Sphere> spheres;
  std::vector<bool> frozen;
  std::vector<int> labels;
  std::vector<std::uint64_t> keys;  // of the spheres (empty: new keys)
};

// One turn of the run schedule (Skeletonizer::advance).
struct Turn {
  double error = 0.0;      // the total error after the step
  bool converged = false;  // it changed by at most options().convergence (relative)
  int split = 0;           // spheres the split decision added
  // run() stops here: no sphere is missing and the spheres have settled (converged, or
  // max_settle_iterations steps after the last split), or spheres are missing and none can split.
  bool done = false;
};

class Skeletonizer {
 public:
  // Starts from one sphere fitted to the whole shape (paper §3.2) and projected on the medial axis.
  Skeletonizer(Shape shape, const SkeletonizerOptions& options);
  Skeletonizer(const Skeletonizer&) = delete;  // the projector refers to shape_
  Skeletonizer& operator=(const Skeletonizer&) = delete;

  // One partition + update (+ projection) step; returns the total error.
  double step();
  // One split round (§3.4); returns the number of spheres added.
  int split();
  // One of the refits with final_lambda that end run(); round 0 keeps the partition, later
  // rounds re-partition first.
  void final_refit(int round);
  // All of them (options().final_rounds), with Phase::FinalRefit after each (`iteration`: the
  // steps so far, as Progress reports them); false when `progress` returned false.
  bool final_refits(const ProgressCallback& progress = {}, int iteration = 0);
  // One turn of the run schedule (paper §3.4): a step, then, while spheres are missing, a split
  // round once the error has converged or split_interval steps have gone by since the last
  // split (or restart_schedule).
  Turn advance();
  // Counts the steps since the last split from 0 again: after an edit the spheres must settle
  // anew before the schedule is done.
  void restart_schedule();
  // Turns until one is done, then the final refits. A cancelled run leaves the state as it was
  // after the last reported turn.
  RunSummary run(const ProgressCallback& progress = {});

  // Dynamic editing. Each re-partitions at once so labels() always covers every sphere; a sphere
  // whose cluster stays below min_cluster_size is moved by the next step(). An id or vertex that
  // names nothing, or removing the last sphere, throws InvalidArgument.
  int add_sphere_at(int vertex);         // the shrinking ball at `vertex`; returns its id
  int add_sphere(const Sphere& sphere);  // as given (e.g. a projected one); returns its id
  void remove_sphere(int id);
  void freeze(int id, bool frozen = true);  // a frozen sphere is neither moved, split nor removed
  // A new target or λ for the steps to come; InvalidOption when out of range.
  void set_target(const Target& target);
  void set_lambda(double lambda);
  // A new density of the shape's vertices (Shape::density; empty: uniform) for the splits and
  // fits to come; InvalidArgument when it is not one value per vertex, finite and >= 0, some > 0.
  void set_density(std::vector<double> density);
  bool wants_more_spheres() const;  // below the count target, or clusters above the threshold
  // Interactive use (EditSession): steps pass over settled spheres, whose members are those of
  // their last fit and which that fit and projection moved by rounding at most, so that a
  // settled skeleton's step costs about its partition. Off by default: a run would then follow
  // other roundings, and its result with them.
  void pass_over_settled(bool on) { pass_over_settled_ = on; }

  SkeletonizerState state() const { return {spheres_, frozen_, labels_, keys_}; }
  // A state of this skeletonizer (InvalidArgument when it does not fit its shape).
  void restore(const SkeletonizerState& state);

  // The medial mesh: the dual of cluster adjacency (every 3-clique a triangle), less the
  // triangles that close cavities when options().open_cavities.
  MedialMesh medial_mesh() const;
  // Every triangle kept: what the refinement measures (vmas/refine.hpp), so that its moves do
  // not depend on which triangles happen to close a pocket.
  MedialMesh adjacency_mesh() const;
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const std::vector<std::uint64_t>& keys() const { return keys_; }  // parallel to spheres()
  int id_of(std::uint64_t key) const;  // the sphere with that key, or -1
  const std::vector<int>& labels() const { return labels_; }  // cluster of every shape vertex
  const std::vector<double>& cluster_errors() const { return cluster_errors_; }  // E(C), eq. 12
  // The area-weighted mean density of each cluster (Shape::density; empty without one).
  const std::vector<double>& cluster_densities() const { return cluster_densities_; }
  bool frozen(int id) const { return frozen_.at(id); }
  const Shape& shape() const { return shape_; }
  const MedialProjector& projector() const { return projector_; }
  const SkeletonizerOptions& options() const { return options_; }
  const Timings& times() const { return times_; }  // of its own stages
  double total_error() const { return total_error_; }

 private:
  // The coarse start of run() when it applies: runs a skeletonizer on the coarsened shape and
  // takes its spheres; counts its steps and cancellation in `summary`; false when it does not
  // apply.
  bool start_coarse(const ProgressCallback& progress, RunSummary& summary);
  // Optimising's fraction (Progress) now; `first_worst` keeps the worst cluster's error at the
  // first call, from which an error threshold's fraction is counted.
  double growth_fraction(double& first_worst) const;
  void repartition();      // partition, then refresh members and errors
  void rebuild_members();  // members_ from labels_
  // Moves spheres with too few vertices to the worst vertices of the worst clusters; true if any
  // moved. `serving_balls_only`: a donor whose worst vertex its ball would serve worse than the
  // vertex's own sphere is passed over.
  bool reseed_tiny_clusters(bool serving_balls_only = false);
  int worst_vertex(int cluster) const;  // the member with the largest weighted E_v: the split seed
  // E(C) times the cluster's area-weighted mean density squared (E(C) without a density):
  // what splitting ranks and the error threshold judges (docs/design.md, "Density").
  double split_error(int cluster) const;
  bool misses_error_threshold() const;  // some free cluster's split_error is above the threshold
  double worst_free_cluster_error() const;  // the largest split_error of a free cluster (0: none)
  int sphere_cap() const;  // with an error threshold: max_spheres, and never more than points
  void check_target_fits(const Target& target) const;  // InvalidOption: more spheres than points
  void refresh_errors(bool spheres_moved);  // E(C) and the total; E_v too if spheres moved
  // The same, E_v of the vertices whose sphere `moved` (by sphere; empty: none) refreshed, or of
  // every vertex when they were not current.
  void refresh_errors(const std::vector<char>& moved);
  // Update (+ projection) of every unfrozen, unsettled sphere; returns which moved, whose vertices'
  // E_v are stale until refresh_errors(moved).
  std::vector<char> fit_and_project(double lambda);
  bool settled(int cluster, double lambda) const;  // its last fit would give it again, nearly
  bool pass_over_settled_ = false;
  void check_id(int id) const;
  void add_key() { keys_.push_back(next_key_++); }  // for a sphere just added

  Shape shape_;
  SkeletonizerOptions options_;
  MedialProjector projector_;
  std::vector<Sphere> spheres_;
  std::vector<bool> frozen_;
  std::vector<std::uint64_t> keys_;
  std::uint64_t next_key_ = 0;
  std::vector<int> labels_;
  std::vector<Sphere> partitioned_spheres_;  // those labels_ are the best of (see partition())
  std::vector<double> vertex_energies_;
  bool energies_current_ = false;  // vertex_energies_ hold E_v of every vertex's sphere as it is
  std::vector<std::vector<int>> members_;
  // What the last fit_and_project did to each sphere (parallel to spheres_; content-checked, so a
  // stale entry only costs a refit).
  struct LastFit {
    bool made = false;
    double lambda = 0.0;
    std::vector<int> members;
    Sphere before, after;
  };
  std::vector<LastFit> last_fits_;
  std::vector<double> cluster_errors_;
  std::vector<double> worst_errors_;  // max E_v / A(v) × error_weight per cluster (split ranking)
  std::vector<double> cluster_densities_;  // area-weighted mean density per cluster (none: empty)
  double total_error_ = 0.0;
  double previous_error_ = 0.0;  // the schedule's: the total error one turn ago
  int since_split_ = 0;          // ... and the steps since the last split or restart
  Timings times_;
};

}  // namespace vmas

#pragma GCC visibility pop
