#pragma once
// Whether a skeleton's spheres are medial balls of a closed input: each centre inside the
// solid, each radius the centre's distance to the surface. The shrinking ball makes them so
// where it converges; where it stops early (a ball's budget of steps, a centre pulled out by a
// refit) a sphere can sit outside or reach through the surface, and a user should hear of it.
#include <vector>

#include "vmas/eval.hpp"
#include "vmas/projection.hpp"
#include "vmas/vmas.hpp"

namespace vmas {

// The counts of InvalidSpheres for `spheres` (in the frame of the projector's shape and of
// `evaluator`'s): a centre is outside where the projector's winding number is at most ½, a
// radius off where it differs from evaluator.distances_to_shape by more than 1 % of `diagonal`.
// `checked` is set; the caller decides whether the input is closed.
InvalidSpheres invalid_spheres(const std::vector<Sphere>& spheres, const MedialProjector& projector,
                               const Evaluator& evaluator, double diagonal);

}  // namespace vmas
