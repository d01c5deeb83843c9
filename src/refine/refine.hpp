#pragma once
// Worst-case refinement after the run. The optimisation lowers an average error (eq. 12), while
// the error users read is a maximum (the two-sided Hausdorff distance of Table 1): a fixed sphere
// budget can leave one feature uncovered, or one junction bulging out, however good the average.
// This stage measures the reconstruction (vmas::evaluate) and tries to move the sphere whose
// removal costs the least energy to the worst-served place, re-settling the optimisation after
// each move; a move is kept only when the measured error drops and the skeleton does not fall
// apart into more components. The sphere count never changes.
#include "vmas/eval.hpp"
#include "vmas/options.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/types.hpp"

namespace vmas {

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

// As above, measuring with `evaluator`, built on the surface with refinement_eval_options().
RefineReport refine_worst_served(Skeletonizer& skeletonizer, Evaluator& evaluator,
                                 const RefineOptions& options,
                                 const ProgressCallback& progress = {});

}  // namespace vmas
