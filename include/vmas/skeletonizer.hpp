#pragma once
// The optimisation state and loop of variational medial axis sampling (paper §3): spheres,
// the partition of the shape among them, per-cluster errors and frozen flags, and the run
// schedule (advance). vmas::skeletonize runs it whole (run), EditSession turn by turn while
// spheres are added, removed or frozen between turns.
//
// Sphere ids are indices into spheres(); removing a sphere shifts the later ids down by one.
// Keys name spheres for their life: a sphere keeps its key whatever is added or removed.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vmas/options.hpp"
#include "vmas/types.hpp"

namespace vmas {
// The shrinking ball on a shape (src/optimise/projection.hpp): internal, so declared before the
// exported part, which would otherwise export its members.
class MedialProjector;
}  // namespace vmas

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// The shape as the method sees it (paper §3.1): positions, outward unit normals, per-vertex
// support area A(v), the diffused quadric Q_v of each vertex, and a symmetric neighbour graph
// (mesh edges, or the k-NN graph of a cloud, its pieces joined by their shortest bridges among
// the 16 nearest neighbours) used for cluster adjacency.
// Vertices regrouped into spatially compact blocks (the leaves of a median-split tree): block b
// holds vertices[offsets[b] .. offsets[b+1]), all inside the ball (centers[b], radii[b]). Lets a
// stage bound a distance for a whole block at once.
struct VertexBlocks {
  std::vector<int> vertices;
  std::vector<int> offsets;
  std::vector<Vec3> centers;
  std::vector<double> radii;

  int size() const { return static_cast<int>(centers.size()); }
};

struct Shape {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;           // unit, outward
  std::vector<double> area;            // A(v) (eq. 4 and 6)
  std::vector<double> density;         // of each vertex (SurfaceInput::density; empty: uniform)
  double density_max = 0.0;            // the largest of them
  std::vector<double> error_weights;   // of each vertex: error_weight's (empty without a density)
  std::vector<Sqem> quadric;           // Q_v (eq. 5 and 7)
  std::vector<int> neighbour_offsets;  // CSR: neighbours of v are
  std::vector<int> neighbours;  //   neighbours[neighbour_offsets[v] .. neighbour_offsets[v+1])
  VertexBlocks blocks;
  bool is_mesh = false;
  double diagonal = 0.0;  // bounding-box diagonal: the unit of every relative length
  double total_area = 0.0;

  int size() const { return static_cast<int>(points.size()); }
  // The weight of an error at density d where spheres are placed: d⁴, so that a cluster's RMS
  // error counts d² times (docs/design.md, "Density").
  static double density_weight(double d) { return (d * d) * (d * d); }
  // ... of vertex v's error, relative to the densest vertex's (1 without a density, and for a
  // uniform one: such a field changes nothing to the bit): what the fits, the split seeds and
  // the refinement's removals weigh by.
  double error_weight(int v) const { return error_weights.empty() ? 1.0 : error_weights[v]; }
  // Sets `density` (checked by the caller: vmas::check_density), `density_max` and
  // `error_weights`.
  void set_density(std::vector<double> values) {
    density = std::move(values);
    density_max = density.empty() ? 0.0 : *std::max_element(density.begin(), density.end());
    error_weights.clear();
    for (double d : density) error_weights.push_back(density_weight(d / density_max));
  }
};

// Builds the shape from a cleaned input. Meshes take their normals and areas from the faces
// (flipped as a whole if the mesh is oriented inward); clouds need normals (InvalidInput
// otherwise).
Shape build_shape(const SurfaceInput& input, const ShapeOptions& options);

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
  // Refining: before every move of the worst-case refinement (src/refine/refine.hpp; round of at most
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
  ~Skeletonizer();
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
  // Every triangle kept: what the refinement measures (src/refine/refine.hpp), so that its moves do
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
  const MedialProjector& projector() const { return *projector_; }
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
  std::unique_ptr<MedialProjector> projector_;
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
