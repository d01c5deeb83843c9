#pragma once
// Whether a skeleton's spheres are medial balls of a closed input: each centre inside the
// solid, each radius the centre's distance to the surface. The shrinking ball makes them so
// where it converges; where it stops early (a ball's budget of steps, a centre pulled out by a
// refit) a sphere can sit outside or reach through the surface, and a user should hear of it.
// And the same winding number's say on a smoothed cloud's estimated normals.
#include <array>
#include <cstddef>
#include <vector>

#include "optimise/projection.hpp"
#include "vmas/eval.hpp"
#include "vmas/vmas.hpp"

namespace vmas {

// The counts of InvalidSpheres for `spheres` (in the frame of the projector's shape and of
// `evaluator`'s): a centre is outside where the projector's winding number is at most ½, a
// radius off where it differs from evaluator.distances_to_shape by more than 1 % of `diagonal`.
// `checked` is set; the caller decides whether the input is closed.
InvalidSpheres invalid_spheres(const std::vector<Sphere>& spheres, const MedialProjector& projector,
                               const Evaluator& evaluator, double diagonal);

// Of `triangles` (sphere indices into `spheres`, frame as above), those whose removal can open a
// tunnel where the solid has one: the centroid of their centres lies outside the closed input,
// or at most `depth` inside it. Through solid, the tunnel's wall would lie as deep as that
// centroid, and the reconstruction's surface so far from the shape's.
std::vector<std::array<int, 3>> where_tunnels_fit(std::vector<std::array<int, 3>> triangles,
                                                  const std::vector<Sphere>& spheres,
                                                  const MedialProjector& projector,
                                                  const Evaluator& evaluator, double depth);

// The orientation of a smoothed cloud's estimated normals turns over only large regions (its
// tree and its views); the small patches it leaves inside out, where noise near thin parts
// misled the tree, are turned over here by the winding number (MedialProjector::inside_out).
// `shape`: built from `surface` (build_shape), to be built again when any normal was turned
// (its quadrics follow the normals). Returns how many, also in report.normals_turned; any other
// surface, and one with holes, is left as it is (0).
std::size_t turn_inside_out_normals(SurfaceInput& surface, PrepareReport& report,
                                    const Shape& shape);

}  // namespace vmas
