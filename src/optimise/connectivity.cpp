#include "optimise/connectivity.hpp"

#include <algorithm>
#include <set>

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

std::vector<std::array<int, 3>> triangles_meeting_nowhere(const Shape& shape,
                                                          const std::vector<int>& labels,
                                                          const MedialMesh& mesh) {
  std::set<std::array<int, 3>> meeting;
  std::vector<int> around;
  for (int v = 0; v < shape.size(); ++v) {
    around.assign(1, labels[v]);
    for (int i = shape.neighbour_offsets[v]; i < shape.neighbour_offsets[v + 1]; ++i)
      around.push_back(labels[shape.neighbours[i]]);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    around.erase(around.begin(), std::lower_bound(around.begin(), around.end(), 0));
    const std::size_t n = around.size();
    for (std::size_t a = 0; a + 2 < n; ++a)
      for (std::size_t b = a + 1; b + 1 < n; ++b)
        for (std::size_t c = b + 1; c < n; ++c) meeting.insert({around[a], around[b], around[c]});
  }
  std::vector<std::array<int, 3>> nowhere;
  for (std::array<int, 3> face : mesh.faces) {
    std::sort(face.begin(), face.end());
    if (!meeting.count(face)) nowhere.push_back(face);
  }
  std::sort(nowhere.begin(), nowhere.end());
  return nowhere;
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
