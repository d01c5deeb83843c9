#pragma once
// The shape's coarse copy (Shape and build_shape are public: vmas/skeletonizer.hpp).
#include <cstddef>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// The shape seen from afar, for the first rounds of a run: about `budget` vertices, one per cell
// of a voxel grid and dominant normal direction (so that the two sides of a thin part stay
// apart; src/core/subsample.hpp). A coarse vertex is its cell's point (position, normal) and
// carries the cell's total area, summed quadric (quadrics add up exactly) and area-weighted mean
// density; two coarse vertices are neighbours when some of their members are. The shape itself when
// it has no more vertices.
Shape coarsen_shape(const Shape& shape, std::size_t budget);

}  // namespace vmas
