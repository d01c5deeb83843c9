#pragma once
// The neighbourhood that holds a cloud's surface together: the shape's graph (build_shape) joins
// whatever it joins, and the fringe trim (supported_by_noise) must not cut what it would join.
#include <cstddef>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

  // A sampling dense in one direction and sparse in the other (the vertices of a mesh of long thin
  // triangles) falls apart into rows at k = 6 (vessel's vertices: 87 pieces); its 16 nearest
  // neighbours join it.
  constexpr int kJoiningNeighbours = 16;

  // Each point's kJoiningNeighbours nearest, the point itself (or a duplicate of it) first, `width`
  // per row.
  struct JoiningNeighbours {
    int width = 0;
    std::vector<int> nearest;

    int size() const { return width > 0 ? static_cast<int>(nearest.size() / width) : 0; }
    const int* row(int point) const { return nearest.data() + std::size_t(point) * width; }
  };
  JoiningNeighbours joining_neighbours(const std::vector<Vec3>& points);

  // Connected pieces of the graph that joins each point to its kJoiningNeighbours nearest: the
  // pieces of a cloud's shape graph (for a graph k up to kJoiningNeighbours). With `among` (a flag
  // per point): the pieces of the flagged points joined by those rows alone, never fewer than the
  // flagged points' own graph has (a point's nearest that are flagged are among its nearest of the
  // flagged ones).
  int joined_pieces(const JoiningNeighbours& neighbours, const std::vector<char>* among = nullptr);

}  // namespace )
}  // namespace vmas
