#pragma once
// Worst-case refinement after the run. The optimisation lowers an average error (eq. 12), while
// the error users read is a maximum (the two-sided Hausdorff distance of Table 1): a fixed sphere
// budget can leave one feature uncovered, or one junction bulging out, however good the average.
// This stage measures the reconstruction (vmas::evaluate) and tries to move the sphere whose
// removal costs the least energy to the worst-served place, re-settling the optimisation after
// each move; a move is kept only when the measured error drops. The sphere count never changes.
#include "vmas/skeletonizer.hpp"
#include "vmas/types.hpp"

namespace vmas {

struct RefineOptions {
  int max_moves = 6;  // relocations tried (0: the stage is off)
  void validate() const;  // throws InvalidOption
};

struct RefineReport {
  int tried = 0, kept = 0;
  double error_before = 0.0, error_after = 0.0;  // two-sided Hausdorff, absolute
  double seconds = 0.0;
};

// `surface` is the input the skeletonizer's shape was built from (same frame).
RefineReport refine_worst_served(Skeletonizer& skeletonizer, const SurfaceInput& surface,
                                 const RefineOptions& options);

}  // namespace vmas
