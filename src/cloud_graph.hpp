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

// Each point's kJoiningNeighbours nearest, the point itself first (`width` per row).
struct JoiningNeighbours {
  int width = 0;
  std::vector<int> nearest;

  const int* row(int point) const { return nearest.data() + std::size_t(point) * width; }
};
JoiningNeighbours joining_neighbours(const std::vector<Vec3>& points);

// Connected pieces of the graph that joins each point to its kJoiningNeighbours nearest: the
// pieces of a cloud's shape graph (for a graph k up to kJoiningNeighbours).
int joined_pieces(const JoiningNeighbours& neighbours);

}  // namespace internal
}  // namespace vmas
