#pragma once
// The neighbourhoods of a cloud's points, and what holds its surface together: the shape's graph
// (build_shape) joins whatever each point's kJoiningNeighbours nearest join, and the fringe trim
// (supported_by_noise) must not cut what it would join.
#include <cstddef>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

// A sampling dense in one direction and sparse in the other (the vertices of a mesh of long thin
// triangles) falls apart into rows at k = 6 (vessel's vertices: 87 pieces); its 16 nearest
// neighbours join it.
constexpr int kJoiningNeighbours = 16;

// The k nearest neighbours of every point, the point itself (or a duplicate of it) first: k + 1
// per row (all the points when there are fewer), row-major.
struct Neighbourhoods {
  int width = 0;
  std::vector<int> indices;

  int size() const { return width > 0 ? static_cast<int>(indices.size() / width) : 0; }
  const int* row(int i) const { return indices.data() + static_cast<std::size_t>(i) * width; }
};

Neighbourhoods k_nearest_all(const std::vector<Vec3>& points, int k);

// Connected pieces of the graph that joins each point to the others of its row: with rows of
// kJoiningNeighbours, the pieces of a cloud's shape graph (for a graph k up to that). With
// `among` (a flag per point): the pieces of the flagged points joined by those rows alone, never
// fewer than the flagged points' own graph has (a point's nearest that are flagged are among its
// nearest of the flagged ones).
int joined_pieces(const Neighbourhoods& neighbours, const std::vector<char>* among = nullptr);

}  // namespace internal
}  // namespace vmas
