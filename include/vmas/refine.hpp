#pragma once
// Worst-case refinement after the run. The optimisation lowers an average error (eq. 12), while
// the error users read is a maximum (the two-sided Hausdorff distance of Table 1): a fixed sphere
// budget can leave one feature uncovered, or one junction bulging out, however good the average.
// This stage measures the reconstruction (vmas::evaluate) and tries to move the sphere whose
// removal costs the least energy to the worst-served place, re-settling the optimisation after
// each move; a move is kept only when the measured error drops and the skeleton does not fall
// apart into more components. The sphere count never changes.
#include "vmas/eval.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

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

// Moves spheres of a finished run (Skeletonizer::run) until a move aimed at the worse side of the
// measured error and one aimed at the other side both fail to lower it, moves gain little, or
// max_moves were tried. `surface` is what the skeletonizer's shape
// was built from, in the same frame: the error is measured against it. `progress` is called
// before every move (Phase::Refining; error = the measured error / diagonal); returning false
// stops with the best state so far. Deterministic for any thread count; frozen spheres are
// neither moved nor removed, and the sphere count stays the same.
RefineReport refine_worst_served(Skeletonizer& skeletonizer, const SurfaceInput& surface,
                                 const RefineOptions& options,
                                 const ProgressCallback& progress = {});

// What the stage measures with: coarser than vmas eval's defaults (the input's vertices only, 4x
// the boundary spacing, 8 refined maxima, maxima only), and a cloud's gaps measured across its
// points' tangent discs (EvalOptions::cloud_as_discs: a sparse sampling's gaps are no error)
// unless the cloud is `smoothed` (PrepareReport::smoothed: the smoothed surface's normals round
// its edges off, and discs there would hide spheres reaching past them, as on a noisy gear's
// teeth). Its Evaluator takes a while to build (a tree over the input's faces) and needs only
// the surface: vmas::skeletonize builds it beside the run and hands it to the overload below.
EvalOptions refinement_eval_options(bool smoothed = false);

// As above, measuring with `evaluator`, built on the surface with refinement_eval_options().
RefineReport refine_worst_served(Skeletonizer& skeletonizer, Evaluator& evaluator,
                                 const RefineOptions& options,
                                 const ProgressCallback& progress = {});

struct FinishReport {
  RefineReport refine;
  double error = 0.0;      // the result's measured two-sided Hausdorff distance, absolute
  bool cancelled = false;  // the progress callback returned false
};

// The end of every run, as vmas::skeletonize, EditSession::finish and Python's
// Skeletonizer.finish make it: the final refits (Skeletonizer::final_refit, options().final_rounds;
// Phase::FinalRefit after each) unless the run made them already (`refitted`: Skeletonizer::run
// does), then the refinement (when options.max_moves > 0), and the error measured with
// `evaluator` (the refinement's last measurement, or one of its own).
FinishReport finish_skeleton(Skeletonizer& skeletonizer, Evaluator& evaluator,
                             const RefineOptions& options, bool refitted,
                             const ProgressCallback& progress = {});

}  // namespace vmas

#pragma GCC visibility pop
