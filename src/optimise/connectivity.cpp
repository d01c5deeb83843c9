#include "optimise/connectivity.hpp"

#include <algorithm>

#include "core/disjoint_sets.hpp"

namespace vmas {

using internal::DisjointSets;

std::vector<std::vector<int>> cluster_adjacency(const Shape& shape, const std::vector<int>& labels,
                                                int cluster_count) {
  std::vector<std::vector<int>> adjacency(cluster_count);
  for (int v = 0; v < shape.size(); ++v) {
    for (int i = shape.neighbour_offsets[v]; i < shape.neighbour_offsets[v + 1]; ++i) {
      const int a = labels[v];
      const int b = labels[shape.neighbours[i]];
      if (a != b && a >= 0 && b >= 0) adjacency[a].push_back(b);
    }
  }
  for (auto& list : adjacency) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adjacency;
}

MedialMesh build_medial_mesh(const std::vector<Sphere>& spheres,
                             const std::vector<std::vector<int>>& adjacency) {
  MedialMesh mesh;
  mesh.spheres = spheres;
  const int count = static_cast<int>(adjacency.size());
  for (int a = 0; a < count; ++a) {
    for (int b : adjacency[a]) {
      if (b <= a) continue;
      mesh.edges.push_back({a, b});
      // Common neighbours c > b of a and b close a triangle.
      auto ia = std::upper_bound(adjacency[a].begin(), adjacency[a].end(), b);
      auto ib = std::upper_bound(adjacency[b].begin(), adjacency[b].end(), b);
      while (ia != adjacency[a].end() && ib != adjacency[b].end()) {
        if (*ia < *ib) {
          ++ia;
        } else if (*ib < *ia) {
          ++ib;
        } else {
          mesh.faces.push_back({a, b, *ia});
          ++ia;
          ++ib;
        }
      }
    }
  }
  return mesh;
}

int component_count(const Shape& shape) {
  DisjointSets components(shape.size());
  for (int v = 0; v < shape.size(); ++v)
    for (int i = shape.neighbour_offsets[v]; i < shape.neighbour_offsets[v + 1]; ++i)
      components.unite(v, shape.neighbours[i]);
  return components.sets();
}

int component_count(const MedialMesh& mesh) {
  DisjointSets components(static_cast<int>(mesh.spheres.size()));
  for (const auto& edge : mesh.edges) components.unite(edge[0], edge[1]);
  for (const auto& face : mesh.faces) {
    components.unite(face[0], face[1]);
    components.unite(face[1], face[2]);
  }
  return components.sets();
}

}  // namespace vmas
