#include "core/cloud_graph.hpp"

#include <algorithm>

#include "core/disjoint_sets.hpp"
#include "core/kdtree.hpp"

namespace vmas {

internal::Neighbourhoods internal::k_nearest_all(const std::vector<Vec3>& points, int k) {
  Neighbourhoods result;
  if (points.empty()) return result;
  const KdTree tree(points);
  const int count = static_cast<int>(points.size());
  result.width = std::min(k + 1, count);
  result.indices.resize(static_cast<std::size_t>(count) * result.width);
#pragma omp parallel
  {
    std::vector<int> indices;
    std::vector<double> squared_distances;
#pragma omp for schedule(static)
    for (int i = 0; i < count; ++i) {
      tree.k_nearest(points[i], result.width, indices, squared_distances);
      // A short answer leaves the rest of the row to the point itself (no link).
      const auto row = result.indices.begin() + static_cast<std::size_t>(i) * result.width;
      std::fill(row, row + result.width, i);
      std::copy_n(indices.begin(), std::min<std::size_t>(indices.size(), result.width), row);
    }
  }
  return result;
}

int internal::joined_pieces(const Neighbourhoods& neighbours, const std::vector<char>* among) {
  const int count = neighbours.size();
  const auto counted = [&](int i) { return among == nullptr || (*among)[i]; };
  DisjointSets pieces(count);
  for (int i = 0; i < count; ++i) {
    if (!counted(i)) continue;
    for (int c = 0; c < neighbours.width; ++c)
      if (counted(neighbours.row(i)[c])) pieces.unite(i, neighbours.row(i)[c]);
  }
  if (among == nullptr) return pieces.sets();
  std::vector<char> is_root(count, 0);
  int flagged_pieces = 0;
  for (int i = 0; i < count; ++i) {
    if (!counted(i)) continue;
    const int root = pieces.find(i);
    flagged_pieces += !is_root[root];
    is_root[root] = 1;
  }
  return flagged_pieces;
}

}  // namespace vmas
