#pragma once
// The neighbourhood that holds a cloud's surface together: the shape's graph (build_shape) joins
// whatever it joins, and the fringe trim (supported_by_noise) must not cut what it would join.
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

// A sampling dense in one direction and sparse in the other (the vertices of a mesh of long thin
// triangles) falls apart into rows at k = 6 (vessel's vertices: 87 pieces); its 16 nearest
// neighbours join it.
constexpr int kJoiningNeighbours = 16;

// Connected pieces of the graph that joins each point to its kJoiningNeighbours nearest: the
// pieces of a cloud's shape graph (for a graph k up to kJoiningNeighbours).
int joined_pieces(const std::vector<Vec3>& points);

}  // namespace internal
}  // namespace vmas
