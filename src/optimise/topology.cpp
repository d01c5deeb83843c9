#include "optimise/topology.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

#include "core/disjoint_sets.hpp"
#include "core/edge_key.hpp"

namespace vmas {

using internal::edge_key;

namespace {

// Gaussian elimination over Z/2 of boundary vectors (sorted ids), one at a time: a vector that
// reduces to nothing lies in the span of those before it.
class Z2Reduction {
 public:
  // Adds `column` (sorted ascending); returns whether it was independent of the ones before.
  bool add(std::vector<int> column) {
    while (!column.empty()) {
      const auto pivot = by_pivot_.find(column.back());
      if (pivot == by_pivot_.end()) {
        const int lowest = column.back();
        by_pivot_.emplace(lowest, std::move(column));
        return true;
      }
      std::vector<int> sum;
      std::set_symmetric_difference(column.begin(), column.end(), pivot->second.begin(),
                                    pivot->second.end(), std::back_inserter(sum));
      column = std::move(sum);
    }
    return false;
  }
  std::size_t rank() const { return by_pivot_.size(); }

 private:
  std::unordered_map<int, std::vector<int>> by_pivot_;  // reduced columns by their largest id
};

}  // namespace

MedialTopology medial_topology(const MedialMesh& medial) {
  MedialTopology topology;
  const int spheres = static_cast<int>(medial.spheres.size());
  std::unordered_map<std::uint64_t, int> edge_ids;
  const auto edge_id = [&](int a, int b) {
    return edge_ids.try_emplace(edge_key(a, b), static_cast<int>(edge_ids.size())).first->second;
  };
  internal::DisjointSets pieces(spheres);
  for (const auto& e : medial.edges) {
    if (e[0] == e[1]) continue;
    edge_id(e[0], e[1]);
    pieces.unite(e[0], e[1]);
  }
  std::set<std::array<int, 3>> seen;  // each triangle once
  Z2Reduction boundaries;
  // The triangles whose slabs reach out least (the smallest spread of their spheres' extents)
  // come last, so that a cavity is opened where its wall covers least.
  const auto reach = [&](int t) {
    const auto& f = medial.faces[t];
    const Sphere& a = medial.spheres[f[0]];
    const Sphere& b = medial.spheres[f[1]];
    const Sphere& c = medial.spheres[f[2]];
    return (b.center - a.center).cross(c.center - a.center).norm() +
           (a.radius + b.radius + c.radius) * (a.radius + b.radius + c.radius);
  };
  std::vector<int> order(medial.faces.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> reaches(order.size());
  double widest = 0.0;
  for (int t : order) widest = std::max(widest, reaches[t] = reach(t));
  // Compared on a grid of a billionth of the widest: the same triangles whatever the frame
  // (vmas skeletonize opens them in the input's, the editor in its working frame), where
  // rounding could otherwise swap two equal ones; ties go by index.
  std::vector<long long> rank(order.size(), 0);
  if (widest > 0.0)
    for (int t : order) rank[t] = std::llround(reaches[t] / widest * 1e9);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return rank[x] > rank[y]; });
  for (int t : order) {
    std::array<int, 3> sorted = medial.faces[t];
    std::sort(sorted.begin(), sorted.end());
    if (sorted[0] == sorted[1] || sorted[1] == sorted[2]) continue;  // not a triangle
    if (!seen.insert(sorted).second) {
      ++topology.duplicate_triangles;
      continue;
    }
    std::vector<int> boundary = {edge_id(sorted[0], sorted[1]), edge_id(sorted[1], sorted[2]),
                                 edge_id(sorted[0], sorted[2])};
    std::sort(boundary.begin(), boundary.end());
    pieces.unite(sorted[0], sorted[1]);
    pieces.unite(sorted[1], sorted[2]);
    if (!boundaries.add(std::move(boundary))) topology.closing_triangles.push_back(t);
  }
  std::sort(topology.closing_triangles.begin(), topology.closing_triangles.end());
  const int edges = static_cast<int>(edge_ids.size());
  const int triangles = static_cast<int>(seen.size());
  topology.components = pieces.sets();
  const int edge_rank = spheres - topology.components;  // rank of ∂1: a spanning forest
  const int triangle_rank = static_cast<int>(boundaries.rank());
  topology.loops = edges - edge_rank - triangle_rank;
  topology.cavities = triangles - triangle_rank;
  return topology;
}

MedialMesh without_cavities(MedialMesh medial) {
  std::vector<char> closing(medial.faces.size(), 0);
  for (int t : medial_topology(medial).closing_triangles) closing[t] = 1;
  std::size_t kept = 0;
  for (std::size_t t = 0; t < medial.faces.size(); ++t)
    if (!closing[t]) medial.faces[kept++] = medial.faces[t];
  medial.faces.resize(kept);
  return medial;
}

SurfaceGenus surface_genus(const SurfaceInput& mesh, const MeshDefects& defects) {
  SurfaceGenus result;
  if (!mesh.is_mesh()) {
    result.why = "a point cloud (no faces)";
    return result;
  }
  if (!defects.closed()) {
    result.why = defects.boundary_edges > 0       ? "the mesh is open"
                 : defects.non_manifold_edges > 0 ? "the mesh has non-manifold edges"
                                                  : "the mesh has misoriented faces";
    return result;
  }
  const int points = static_cast<int>(mesh.points.size());
  internal::DisjointSets pieces(points);
  for (const auto& f : mesh.faces) {
    pieces.unite(f[0], f[1]);
    pieces.unite(f[1], f[2]);
  }
  // V − E + F per piece (each edge lies on two faces: E = 3F / 2).
  std::map<int, int> order;  // root -> piece, by first face
  std::vector<long long> twice_characteristic;
  std::vector<char> counted(points, 0);
  for (const auto& f : mesh.faces) {
    const int root = pieces.find(f[0]);
    const auto [entry, fresh] = order.emplace(root, static_cast<int>(order.size()));
    if (fresh) twice_characteristic.push_back(0);
    long long& chi2 = twice_characteristic[entry->second];
    chi2 += 2 - 3;  // a face, and half of each of its three edges
    for (int v : f)
      if (!counted[v]) {
        counted[v] = 1;
        chi2 += 2;
      }
  }
  for (long long chi2 : twice_characteristic) {
    // 2χ = 4 − 4g
    if ((4 - chi2) % 4 != 0 || chi2 > 4) {
      result.genus.clear();
      result.why = "a piece's Euler characteristic fits no closed surface (a pinched vertex)";
      return result;
    }
    result.genus.push_back(static_cast<int>((4 - chi2) / 4));
  }
  result.known = true;
  return result;
}

}  // namespace vmas
