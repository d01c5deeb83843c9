#pragma once
// Dynamic skeletonization (paper §4, "Interactive modification"): a Skeletonizer optimised
// without pause in a worker thread while other threads edit it. Edits are queued and applied
// between steps; after every step the state is published as a snapshot that any thread may
// read. The engine of `vmas edit`; usable by any front end.
//
// Spheres are named by the Skeletonizer's keys, which stay with a sphere for its life (its ids
// shift when one is removed), so that an edit made against an older snapshot still means the
// sphere the user pointed at, or nothing. The worker follows the run schedule of
// Skeletonizer::run (Skeletonizer::advance), restarted by every edit, and goes on after it is
// done, more slowly, so that edits re-settle the skeleton.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vmas/skeletonizer.hpp"
#include "vmas/vmas.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

struct EditSnapshot {
  std::uint64_t version = 0;  // grows with every published state
  int iteration = 0;          // steps so far
  double steps_per_second = 0.0;
  double error = 0.0;  // total error Σ E_v / A(shape)
  bool paused = false;
  int target_spheres = 0;
  double lambda = 0.0;
  std::vector<std::uint64_t> keys;  // of every sphere, in the order of `spheres`
  std::vector<Sphere> spheres;
  std::vector<bool> frozen;
  std::vector<int> labels;  // cluster (index into `spheres`) of every shape vertex
  MedialMesh mesh;          // spheres, edges and faces (shape coordinates)
  std::size_t dropped_edits = 0;  // edits that meant nothing when their turn came (a sphere
                                  // already gone, a split beyond the most spheres)
  int undo_steps = 0, redo_steps = 0;  // edits undo() and redo() can take back / make again
  // finish(): how many were done, whether the spheres are still those of the last one (no edit
  // and no step since), and the measured two-sided Hausdorff error, relative to the diagonal,
  // before and after it.
  int finishes = 0;
  bool finished = false;
  double error_before_finish = 0.0, error_after_finish = 0.0;
  // A finish under way (asked for and not done or cancelled yet): its phase ("waiting",
  // "measuring", "final refits", "refining", "fresh run") and the fraction of that phase done;
  // the spheres meanwhile are those from before it.
  bool finishing = false;
  std::string finish_phase;
  double finish_fraction = 0.0;
  int cancelled_finishes = 0;
  // The two-sided Hausdorff error relative to the diagonal (the refinement's measure), taken
  // every few seconds once the spheres have settled, and the step it was taken after (-1: none
  // yet).
  double measured_error = 0.0;
  int measured_at_iteration = -1;
  // The density of the shape's vertices (Shape::density; null: uniform), shared with the
  // session, and how many times it has changed (painted, set, undone).
  std::shared_ptr<const std::vector<double>> density;
  std::uint64_t density_changes = 0;
  // The topology of `mesh` (issue 50; docs/design.md, "Loops brought to a closed mesh's genus"):
  // medial_topology's Betti numbers (its closing_triangles, indices into mesh.faces, each close a
  // cavity), the genus of the shape's pieces when known (the session's input_genus), and the
  // loops beyond that genus, each as its sphere ids around it, shortest first (extra_loops;
  // none when the genus is unknown). Computed again only when the mesh changed.
  MedialTopology topology;
  SurfaceGenus input_genus;
  std::vector<std::vector<int>> extra_loops;
};

// What finish() measures against and how it refines.
struct FinishOptions {
  // The points (and faces) the shape was built from, in its frame (PreparedShape::surface);
  // empty: the shape's own points and normals.
  SurfaceInput surface;
  RefineOptions refine;
  EvalOptions measure = refinement_eval_options();  // how the finish measures its error
  // A fresh run for a session whose spheres no hand has touched (none split, removed or frozen,
  // nothing undone; the count and λ may have changed): called by finish() with the session's
  // options of that moment, e.g. vmas::best_start on the prepared shape, so that such a finish
  // gives what vmas skeletonize gives. finish() keeps whichever of its state and the finished
  // live skeleton measures better. Empty: none. The callback may throw Cancelled when the
  // progress callback it is given returns false (the session is being destroyed).
  std::function<BestStart(const SkeletonizerOptions&, const ProgressCallback&)> fresh_run;
};

// What `vmas edit` finishes with: the surface of `prepared`, options.refine, and for an untouched
// session vmas::best_start on a copy of `prepared` (held by the callback).
FinishOptions finish_as_skeletonize_does(const PreparedShape& prepared, const Options& options);

class EditSession {
 public:
  // Most edits waiting at once; more is an error (a front end gone wild, or an attack).
  static constexpr std::size_t kMaxPendingEdits = 1000;

  // Starts optimising at once (from one sphere, splitting up to options.target), with
  // `threads` OpenMP threads in the worker (0: OpenMP's default, all cores). `input_genus`: the
  // genus of the shape's pieces when known (a closed mesh's, PreparedShape::result.input_genus),
  // which snapshots count extra loops against.
  EditSession(Shape shape, const SkeletonizerOptions& options, int threads = 0,
              FinishOptions finish = {}, SurfaceGenus input_genus = {});
  ~EditSession();  // stops the worker
  EditSession(const EditSession&) = delete;
  EditSession& operator=(const EditSession&) = delete;

  // Edits, applied before the next step. Each throws InvalidOption for a count or λ out of its
  // range, InvalidArgument when it cannot mean anything (a vertex out of range, a key not in the
  // latest snapshot, too many edits waiting).
  // Spheres by key, one edit (one undo step) for all of them. A frozen sphere is not removed,
  // nor the last one; the count target goes down by the spheres removed (pending growth stays).
  void remove(const std::vector<std::uint64_t>& keys);
  void remove(std::uint64_t key) { remove(std::vector<std::uint64_t>{key}); }
  void split_at(int vertex);  // a new sphere: the shrinking ball at `vertex`
  void freeze(const std::vector<std::uint64_t>& keys, bool frozen);
  void freeze(std::uint64_t key, bool frozen) { freeze(std::vector<std::uint64_t>{key}, frozen); }
  void set_target_spheres(int count);  // grows by splitting, shrinks by removing small clusters
  // The density (docs/design.md, "Density"), one edit each: a brush stroke adds `amount` at
  // `vertex`, falling smoothly to nothing at `radius` (a fraction of the diagonal), never below
  // 0 (a uniform density of 1 when there was none; dropped when it would leave every vertex at
  // 0); set_density gives every vertex its value (empty: uniform). InvalidOption for a radius
  // out of (0, 1] or an amount beyond ±kMaxDensityStroke, InvalidArgument for a vertex out of
  // range or a density that vmas::check_density refuses.
  static constexpr double kMaxDensityStroke = 100.0;
  void paint_density(int vertex, double radius, double amount);
  void set_density(std::vector<double> density);
  void set_lambda(double lambda);
  // Relative to the value when the edit's turn comes, so that quick edits add up (five +1
  // before the worker's next turn are +5): the count target (the sphere count when growing to
  // an error threshold) by `by`, kept within 1 and the most spheres; λ times `factor` (> 0).
  void change_target_spheres(int by);
  void scale_lambda(double factor);
  // Takes back the last edit (add, split, remove, freeze, count, λ, density; not pause), at most
  // kUndoSteps of them: the spheres, freezes, count and λ of that moment come back and the
  // optimisation goes on from there. redo() makes an undone edit again, until a new edit.
  // Either does nothing when there is nothing to take back or make again.
  static constexpr int kUndoSteps = 64;
  void undo();
  void redo();
  void pause(bool paused);
  // Ends the optimisation as vmas::skeletonize does: the final refits, then the worst-case
  // refinement (src/refine/refine.hpp), on the current spheres; frozen spheres never move, and when
  // the measured error would grow the spheres stay as they were. Then the session pauses, so that the finished skeleton stays until the next edit or resume. An edit
  // of its own: undo() takes it back.
  void finish();
  // Stops a finish under way: the skeleton, its pause and its measured error stay as they were
  // before it (no undo step). Nothing when no finish is under way. Edits made meanwhile wait
  // for the finish's end (`vmas edit` refuses them: a page would show a finished skeleton that
  // they then change).
  void cancel_finish();
  bool finishing() const;  // a finish asked for and not done or cancelled yet

  EditSnapshot snapshot() const;
  // Its points, normals and graph; its density is the worker's (snapshot().density is the one
  // to read).
  const Shape& shape() const;
  // The surface -> medial distance of every shape vertex to `mesh` (a snapshot's), relative to
  // the diagonal: vmas eval's per-vertex error, for a heat map. Computed in the calling thread.
  std::vector<float> vertex_errors(const MedialMesh& mesh) const;
  // Waits until a snapshot newer than `version` is published, or `timeout_ms` passes; returns
  // the latest snapshot's version.
  std::uint64_t wait_for_version(std::uint64_t version, int timeout_ms) const;

 private:
  struct Impl;  // the worker thread, the edit queue, the undo history
  std::unique_ptr<Impl> impl_;
};

}  // namespace vmas

#pragma GCC visibility pop
