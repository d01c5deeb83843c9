#include "prepare/mesh_sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/edge_key.hpp"

namespace vmas {

using internal::edge_key;

namespace {

constexpr double kReferencePoints = 1e4;    // s: the spacing of this many points over the area
constexpr double kCoarseEdgeInSpacings = 3.0;  // a face with an edge this many s long ...
constexpr double kThinAspect = 4.0;  // ... and its height on it this many times shorter is coarse
constexpr double kLongEdgeInSpacings = 10.0;  // so is a face of any shape with an edge this long
constexpr double kCoarseAreaShare = 0.01;      // a mesh is coarse with this much coarse area
constexpr double kEdgeLimitInSpacings = 1.5;   // longer edges are split ...
constexpr double kFlatInSpacings = 0.01;       // ... and faces this flat flipped
constexpr int kMaxRounds = 64;                 // each halves the longest edges: never reached

double triangle_area(const SurfaceInput& mesh, const std::array<int, 3>& f) {
  const Vec3& a = mesh.points[f[0]];
  return 0.5 * (mesh.points[f[1]] - a).cross(mesh.points[f[2]] - a).norm();
}

double squared_length(const SurfaceInput& mesh, int a, int b) {
  return (mesh.points[a] - mesh.points[b]).squaredNorm();
}

// A long, thin face: what a CAD exporter leaves across a flat face or along a straight wall. A
// well-shaped face samples its part of the surface as evenly as the rest, unless it is so large
// that the whole mesh has only about a hundred vertices (a low-poly model: too few for its spheres).
bool coarse_face(const SurfaceInput& mesh, const std::array<int, 3>& f, double spacing) {
  const double longest =
      std::sqrt(std::max({squared_length(mesh, f[0], f[1]), squared_length(mesh, f[1], f[2]),
                          squared_length(mesh, f[2], f[0])}));
  const double height = 2.0 * triangle_area(mesh, f) / longest;
  return longest > kCoarseEdgeInSpacings * spacing &&
         (longest > kThinAspect * height || longest > kLongEdgeInSpacings * spacing);
}

// The vertices of a mesh in cells of a grid, to find those near a point; each with the unit
// normal of the surface there (to tell the two sides of a thin wall apart).
class VertexGrid {
 public:
  VertexGrid(const SurfaceInput& mesh, double cell) : cell_(cell) {
    normals_.assign(mesh.points.size(), Vec3::Zero());
    for (const auto& f : mesh.faces) {
      const Vec3 area_normal = (mesh.points[f[1]] - mesh.points[f[0]])
                                   .cross(mesh.points[f[2]] - mesh.points[f[0]]);
      for (int v : f) normals_[v] += area_normal;
    }
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
      normals_[v].normalize();
      cells_[key(mesh.points[v])].push_back(static_cast<int>(v));
    }
  }

  void add(const Vec3& point, const Vec3& normal) {
    cells_[key(point)].push_back(static_cast<int>(normals_.size()));
    normals_.push_back(normal);
  }

  // Whether a vertex on the side of the surface that faces `normal` lies within one cell of
  // `point`.
  bool occupied_near(const SurfaceInput& mesh, const Vec3& point, const Vec3& normal) const {
    const Eigen::Array3i centre = cell_of(point);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find(pack(centre + Eigen::Array3i(dx, dy, dz)));
          if (found == cells_.end()) continue;
          for (int v : found->second)
            if ((mesh.points[v] - point).squaredNorm() < cell_ * cell_ && normals_[v].dot(normal) > 0.0)
              return true;
        }
    return false;
  }

 private:
  Eigen::Array3i cell_of(const Vec3& p) const { return (p / cell_).array().floor().cast<int>(); }
  static std::uint64_t pack(const Eigen::Array3i& c) {
    const auto bits = [](int x) { return static_cast<std::uint64_t>(x + (1 << 20)) & 0x1fffff; };
    return bits(c.x()) | bits(c.y()) << 21 | bits(c.z()) << 42;
  }
  std::uint64_t key(const Vec3& p) const { return pack(cell_of(p)); }

  double cell_;
  std::vector<Vec3> normals_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// One round: each edge longer than `limit` split at its midpoint unless a vertex on the same side
// of the surface lies within half the limit of it (the long sides of a fan of slivers: one in a
// few gets vertices). Returns whether any edge was split.
bool split_long_edges(SurfaceInput& mesh, double limit, VertexGrid& grid) {
  const double squared_limit = limit * limit;
  std::unordered_map<std::uint64_t, int> midpoints;  // of the edges looked at; −1: not split
  bool any = false;
  const auto midpoint = [&](int a, int b, const Vec3& normal) {
    if (squared_length(mesh, a, b) <= squared_limit) return -1;
    const auto [entry, fresh] = midpoints.try_emplace(edge_key(a, b), -1);
    if (!fresh) return entry->second;
    const Vec3 middle = 0.5 * (mesh.points[a] + mesh.points[b]);
    if (grid.occupied_near(mesh, middle, normal)) return -1;
    entry->second = static_cast<int>(mesh.points.size());
    mesh.points.push_back(middle);
    if (!mesh.density.empty()) mesh.density.push_back(0.5 * (mesh.density[a] + mesh.density[b]));
    grid.add(middle, normal);
    any = true;
    return entry->second;
  };
  std::vector<std::array<int, 3>> faces;
  faces.reserve(mesh.faces.size());
  for (std::array<int, 3> f : mesh.faces) {
    const Vec3 normal =
        (mesh.points[f[1]] - mesh.points[f[0]]).cross(mesh.points[f[2]] - mesh.points[f[0]]).normalized();
    std::array<int, 3> split{};  // split[i]: the midpoint of the edge f[i] f[i+1], or −1
    int count = 0;
    for (int i = 0; i < 3; ++i) count += (split[i] = midpoint(f[i], f[(i + 1) % 3], normal)) >= 0;
    if (count == 0) {
      faces.push_back(f);
      continue;
    }
    if (count == 3) {
      faces.push_back({f[0], split[0], split[2]});
      faces.push_back({split[0], f[1], split[1]});
      faces.push_back({split[2], split[1], f[2]});
      faces.push_back({split[0], split[1], split[2]});
      continue;
    }
    // Turned (keeping the orientation) so that the edge f[0] f[1] is split, and with two splits
    // f[1] f[2] too.
    int turn = 0;
    while (split[turn] < 0 || (count == 2 && split[(turn + 1) % 3] < 0)) ++turn;
    std::rotate(f.begin(), f.begin() + turn, f.end());
    std::rotate(split.begin(), split.begin() + turn, split.end());
    const int a = f[0], b = f[1], c = f[2], ab = split[0], bc = split[1];
    if (count == 1) {
      faces.push_back({a, ab, c});
      faces.push_back({ab, b, c});
      continue;
    }
    faces.push_back({ab, b, bc});
    // The quad a, ab, bc, c cut along its shorter diagonal.
    if (squared_length(mesh, a, bc) <= squared_length(mesh, ab, c)) {
      faces.push_back({a, ab, bc});
      faces.push_back({a, bc, c});
    } else {
      faces.push_back({a, ab, c});
      faces.push_back({ab, bc, c});
    }
  }
  mesh.faces = std::move(faces);
  return any;
}

// Lawson's flips: an edge between two faces that lie in one plane (within `tolerance`) is
// flipped while the angles facing it sum to more than π, so that the long slivers left beside
// the split edges become faces between the new vertices. The surface does not move.
void flip_to_delaunay(SurfaceInput& mesh, double tolerance) {
  // Each edge's faces: −1 for none yet, −2 for a third (such an edge is never flipped).
  std::unordered_map<std::uint64_t, std::array<int, 2>> faces_of;
  std::vector<std::uint64_t> queue;
  for (int f = 0; f < static_cast<int>(mesh.faces.size()); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t key = edge_key(mesh.faces[f][i], mesh.faces[f][(i + 1) % 3]);
      const auto [entry, fresh] = faces_of.try_emplace(key, std::array<int, 2>{f, -1});
      if (fresh) {
        queue.push_back(key);
        continue;
      }
      if (entry->second[1] == -1) entry->second[1] = f;
      else entry->second = {-2, -2};
    }
  const auto third = [&](int f, int a, int b) {
    for (int v : mesh.faces[f])
      if (v != a && v != b) return v;
    return -1;
  };
  const auto angle = [&](int at, int a, int b) {
    const Vec3 u = mesh.points[a] - mesh.points[at], w = mesh.points[b] - mesh.points[at];
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  const auto normal = [&](int a, int b, int c) {
    return Vec3((mesh.points[b] - mesh.points[a]).cross(mesh.points[c] - mesh.points[a]));
  };
  const auto replace = [&](int a, int b, int from, int to) {
    for (int& f : faces_of[edge_key(a, b)])
      if (f == from) f = to;
  };
  // Each flip makes an angle sum below π: a bound far above what a flat region needs.
  std::size_t budget = 20 * faces_of.size();
  for (std::size_t next = 0; next < queue.size() && budget > 0; ++next) {
    const std::uint64_t key = queue[next];
    const auto found = faces_of.find(key);
    if (found == faces_of.end() || found->second[0] < 0 || found->second[1] < 0) continue;
    const int f1 = found->second[0], f2 = found->second[1];
    // f1 = (a, b, c) and f2 = (b, a, d), both turning the same way.
    std::array<int, 3> first = mesh.faces[f1];
    const int low = static_cast<int>(key >> 32), high = static_cast<int>(key & 0xffffffffu);
    while (!((first[0] == low && first[1] == high) || (first[0] == high && first[1] == low)))
      std::rotate(first.begin(), first.begin() + 1, first.end());
    const int a = first[0], b = first[1], c = first[2], d = third(f2, a, b);
    const auto& second = mesh.faces[f2];
    bool reversed = false;
    for (int i = 0; i < 3; ++i) reversed |= second[i] == b && second[(i + 1) % 3] == a;
    if (d < 0 || d == c || !reversed || faces_of.count(edge_key(c, d))) continue;
    if (angle(c, a, b) + angle(d, b, a) <= M_PI + 1e-12) continue;
    const Vec3 n1 = normal(a, b, c), n2 = normal(b, a, d);
    if (std::abs(n1.normalized().dot(mesh.points[d] - mesh.points[a])) > tolerance ||
        std::abs(n2.normalized().dot(mesh.points[c] - mesh.points[a])) > tolerance)
      continue;
    // The new faces must turn as the old ones (a convex quad).
    if (!(normal(c, a, d).dot(n1) > 0.0) || !(normal(d, b, c).dot(n1) > 0.0)) continue;
    mesh.faces[f1] = {c, a, d};
    mesh.faces[f2] = {d, b, c};
    faces_of.erase(found);
    faces_of[edge_key(c, d)] = {f1, f2};
    replace(b, c, f1, f2);
    replace(a, d, f2, f1);
    for (const std::uint64_t around : {edge_key(a, c), edge_key(b, c), edge_key(a, d), edge_key(b, d)})
      queue.push_back(around);
    --budget;
  }
}

}  // namespace

MeshSampling sample_coarse_mesh(SurfaceInput& mesh) {
  MeshSampling sampling;
  if (!mesh.is_mesh()) return sampling;
  double area = 0.0;
  for (const auto& f : mesh.faces) area += triangle_area(mesh, f);
  const double spacing = std::sqrt(area / kReferencePoints);
  if (!(spacing > 0.0)) return sampling;
  double coarse_area = 0.0;
  for (const auto& f : mesh.faces)
    if (coarse_face(mesh, f, spacing))
      coarse_area += triangle_area(mesh, f);
  if (!(coarse_area > kCoarseAreaShare * area)) return sampling;

  const double limit = kEdgeLimitInSpacings * spacing;
  sampling.vertices_before = mesh.points.size();
  sampling.edge_limit = limit;
  VertexGrid grid(mesh, 0.5 * limit);
  for (int round = 0; round < kMaxRounds && split_long_edges(mesh, limit, grid); ++round)
    flip_to_delaunay(mesh, kFlatInSpacings * spacing);
  // Sampled meshes carry no per-vertex normals (a mesh's come from its faces).
  mesh.normals.clear();
  return sampling;
}

}  // namespace vmas
