#include "vmas/connectivity.hpp"

#include <algorithm>

namespace vmas {

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

std::vector<std::array<int, 3>> dual_triangles(const Shape& shape, const std::vector<int>& labels) {
  std::vector<std::array<int, 3>> faces;
  auto begin = [&](int v) { return shape.neighbours.begin() + shape.neighbour_offsets[v]; };
  auto end = [&](int v) { return shape.neighbours.begin() + shape.neighbour_offsets[v + 1]; };
  for (int u = 0; u < shape.size(); ++u)
    for (auto v = begin(u); v != end(u); ++v) {
      if (*v <= u || labels[*v] == labels[u]) continue;
      for (auto w = v + 1; w != end(u); ++w) {
        if (*w <= u || labels[*w] == labels[u] || labels[*w] == labels[*v]) continue;
        if (!std::binary_search(begin(*v), end(*v), *w)) continue;
        std::array<int, 3> f = {labels[u], labels[*v], labels[*w]};
        std::sort(f.begin(), f.end());
        faces.push_back(f);
      }
    }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
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

}  // namespace vmas
