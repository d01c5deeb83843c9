#include "optimise/topology.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
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

namespace {

// A medial mesh as a graph of centres: its edges (listed, and those of its triangles) by id,
// with their lengths, and the triangles' boundaries reduced over Z/2.
struct CentreGraph {
  std::vector<std::array<int, 2>> edges;
  std::unordered_map<std::uint64_t, int> edge_ids;
  std::vector<std::vector<std::pair<int, int>>> out;  // per sphere: (neighbour, edge id)
  std::vector<double> lengths;                        // per edge id
  std::set<std::array<int, 3>> triangles;             // sorted
  Z2Reduction filled;                                 // boundaries of the triangles so far

  explicit CentreGraph(const MedialMesh& medial) : out(medial.spheres.size()) {
    for (const auto& e : medial.edges) id_of(medial, e[0], e[1]);
    for (const auto& f : medial.faces) add_triangle(medial, f[0], f[1], f[2]);
  }
  int id_of(const MedialMesh& medial, int a, int b) {
    const auto [entry, fresh] =
        edge_ids.try_emplace(internal::edge_key(a, b), static_cast<int>(edges.size()));
    if (fresh && a != b) {
      edges.push_back({a, b});
      lengths.push_back((medial.spheres[a].center - medial.spheres[b].center).norm());
      out[a].emplace_back(b, entry->second);
      out[b].emplace_back(a, entry->second);
    }
    return entry->second;
  }
  // Returns whether the triangle is new (and not degenerate).
  bool add_triangle(const MedialMesh& medial, int a, int b, int c) {
    std::array<int, 3> sorted = {a, b, c};
    std::sort(sorted.begin(), sorted.end());
    if (sorted[0] == sorted[1] || sorted[1] == sorted[2] || !triangles.insert(sorted).second)
      return false;
    std::vector<int> boundary = {id_of(medial, sorted[0], sorted[1]),
                                 id_of(medial, sorted[1], sorted[2]),
                                 id_of(medial, sorted[0], sorted[2])};
    std::sort(boundary.begin(), boundary.end());
    filled.add(std::move(boundary));
    return true;
  }
  // The shortest path of centres from `from` to `to` that does not take edge `skip` (spheres,
  // `from` first; empty when there is none).
  std::vector<int> shortest_path(int from, int to, int skip) const {
    std::vector<double> distance(out.size(), std::numeric_limits<double>::infinity());
    std::vector<int> previous(out.size(), -1);
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    distance[from] = 0.0;
    queue.emplace(0.0, from);
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (v == to) break;
      if (d > distance[v]) continue;
      for (const auto& [w, e] : out[v]) {
        if (e == skip || !(d + lengths[e] < distance[w])) continue;
        distance[w] = d + lengths[e];
        previous[w] = v;
        queue.emplace(distance[w], w);
      }
    }
    std::vector<int> path;
    if (previous[to] < 0) return path;
    for (int v = to; v != -1; v = previous[v]) path.push_back(v);
    std::reverse(path.begin(), path.end());
    return path;
  }
};

// A loop to fill: its spheres in order, its edges (sorted ids) and its length.
struct Loop {
  std::vector<int> spheres;
  std::vector<int> edges;
  double length = 0.0;
};

// The triangles filling `loop` (at least 3 spheres): one ear at a time, the one whose diagonal
// is shortest (ties: the first).
std::vector<std::array<int, 3>> triangulate(std::vector<int> loop, const MedialMesh& medial) {
  std::vector<std::array<int, 3>> triangles;
  const auto centre = [&](int s) { return medial.spheres[s].center; };
  while (loop.size() > 3) {
    const std::size_t n = loop.size();
    std::size_t ear = 0;
    double shortest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
      const double diagonal = (centre(loop[(i + n - 1) % n]) - centre(loop[(i + 1) % n])).norm();
      if (diagonal < shortest) shortest = diagonal, ear = i;
    }
    triangles.push_back({loop[(ear + n - 1) % n], loop[ear], loop[(ear + 1) % n]});
    loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  triangles.push_back({loop[0], loop[1], loop[2]});
  return triangles;
}

}  // namespace

std::vector<std::vector<int>> extra_loops(const MedialMesh& medial, int loops) {
  int extra = medial_topology(medial).loops - loops;
  if (extra <= 0) return {};
  CentreGraph graph(medial);
  // The shortest cycle through each edge, shortest first (ties by their edges: any frame gives
  // the same order where the lengths agree).
  std::vector<Loop> candidates;
  std::set<std::vector<int>> seen;
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    Loop loop;
    loop.spheres = graph.shortest_path(graph.edges[e][0], graph.edges[e][1], e);
    if (loop.spheres.size() < 3) continue;
    for (std::size_t i = 0; i < loop.spheres.size(); ++i) {
      const int id = graph.edge_ids.at(
          internal::edge_key(loop.spheres[i], loop.spheres[(i + 1) % loop.spheres.size()]));
      loop.edges.push_back(id);
      loop.length += graph.lengths[id];
    }
    std::sort(loop.edges.begin(), loop.edges.end());
    if (seen.insert(loop.edges).second) candidates.push_back(std::move(loop));
  }
  std::sort(candidates.begin(), candidates.end(), [](const Loop& x, const Loop& y) {
    return x.length != y.length ? x.length < y.length : x.edges < y.edges;
  });
  std::vector<std::vector<int>> found;
  for (Loop& loop : candidates) {
    if (static_cast<int>(found.size()) == extra) break;
    // Independent of the triangles' boundaries and of the loops found before: a loop of its
    // own (filling it fills exactly this class).
    if (graph.filled.add(loop.edges)) found.push_back(std::move(loop.spheres));
  }
  return found;
}

MedialMesh fill_extra_loops(MedialMesh medial, int loops, int* filled) {
  const std::vector<std::vector<int>> found = extra_loops(medial, loops);
  if (filled) *filled = static_cast<int>(found.size());
  if (found.empty()) return medial;
  CentreGraph graph(medial);
  for (const std::vector<int>& loop : found)
    for (const auto& [a, b, c] : triangulate(loop, medial)) {
      for (const auto& [u, v] : {std::pair(a, b), std::pair(b, c), std::pair(a, c)})
        if (!graph.edge_ids.count(internal::edge_key(u, v))) medial.edges.push_back({u, v});
      if (graph.add_triangle(medial, a, b, c)) medial.faces.push_back({a, b, c});
    }
  return medial;
}

MedialMesh open_missing_loops(MedialMesh medial, int loops,
                              const std::vector<std::array<int, 3>>& candidates, int* opened) {
  if (opened) *opened = 0;
  int have = medial_topology(medial).loops;
  if (have >= loops || candidates.empty()) return medial;
  const std::set<std::array<int, 3>> allowed(candidates.begin(), candidates.end());
  std::vector<int> order;
  std::vector<double> area(medial.faces.size(), 0.0);
  for (int t = 0; t < static_cast<int>(medial.faces.size()); ++t) {
    std::array<int, 3> sorted = medial.faces[t];
    std::sort(sorted.begin(), sorted.end());
    if (!allowed.count(sorted)) continue;
    const Vec3& a = medial.spheres[sorted[0]].center;
    area[t] = (medial.spheres[sorted[1]].center - a).cross(medial.spheres[sorted[2]].center - a).norm();
    order.push_back(t);
  }
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return area[x] > area[y]; });
  std::vector<char> removed(medial.faces.size(), 0);
  const auto without_removed = [&] {
    MedialMesh kept = medial;
    kept.faces.clear();
    for (std::size_t t = 0; t < medial.faces.size(); ++t)
      if (!removed[t]) kept.faces.push_back(medial.faces[t]);
    return kept;
  };
  for (int t : order) {
    if (have >= loops) break;
    removed[t] = 1;
    const int now = medial_topology(without_removed()).loops;
    if (now > have) {
      have = now;
      if (opened) ++*opened;
    } else {
      removed[t] = 0;  // it closed a cavity, or its loop is another triangle's too
    }
  }
  return without_removed();
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
