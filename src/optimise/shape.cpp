#include "optimise/shape.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

#include "core/cloud_graph.hpp"
#include "core/density_mean.hpp"
#include "core/disjoint_sets.hpp"
#include "core/kdtree.hpp"
#include "core/subsample.hpp"
#include "vmas/error.hpp"
#include "vmas/vmas.hpp"

namespace vmas {

void ShapeOptions::validate() const {
  if (k < 3 || k > 100)
    throw InvalidOption("k", "must be between 3 and 100 (got " + std::to_string(k) + ")");
}

namespace {

// Turns a list of directed pairs into a symmetric CSR graph without repeats or self loops,
// neighbours in ascending order. Buckets by vertex, then sorts each short list: sorting all
// pairs at once was the costliest part of building a shape.
void set_neighbour_graph(Shape& shape, const std::vector<std::pair<int, int>>& pairs) {
  const int n = shape.size();
  std::vector<int> offsets(n + 1, 0);
  for (const auto& [from, to] : pairs) {
    if (from == to) continue;
    ++offsets[from + 1];
    ++offsets[to + 1];
  }
  for (int v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
  std::vector<int> both(offsets[n]);
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (const auto& [from, to] : pairs) {
    if (from == to) continue;
    both[fill[from]++] = to;
    both[fill[to]++] = from;
  }
  shape.neighbour_offsets.assign(n + 1, 0);
  shape.neighbours.clear();
  shape.neighbours.reserve(both.size());
  for (int v = 0; v < n; ++v) {
    const auto first = both.begin() + offsets[v], last = both.begin() + offsets[v + 1];
    std::sort(first, last);
    shape.neighbours.insert(shape.neighbours.end(), first, std::unique(first, last));
    shape.neighbour_offsets[v + 1] = static_cast<int>(shape.neighbours.size());
  }
}

void build_mesh_attributes(const SurfaceInput& input, Shape& shape) {
  const int n = shape.size();
  // A closed mesh oriented inward has negative signed volume: flip every face normal then.
  double signed_volume = 0.0;
  for (const auto& f : input.faces)
    signed_volume += input.points[f[0]].dot(input.points[f[1]].cross(input.points[f[2]]));
  const double orientation = signed_volume < 0.0 ? -1.0 : 1.0;

  std::vector<Vec3> normal_sum(n, Vec3::Zero());
  shape.area.assign(n, 0.0);
  shape.quadric.assign(n, Sqem{});
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * input.faces.size());
  for (const auto& f : input.faces) {
    const Vec3 cross =
        (input.points[f[1]] - input.points[f[0]]).cross(input.points[f[2]] - input.points[f[0]]) *
        orientation;
    const double face_area = 0.5 * cross.norm();
    if (!(face_area > 0.0)) continue;
    const Vec3 normal = cross.normalized();
    for (int corner = 0; corner < 3; ++corner) {
      const int v = f[corner];
      shape.area[v] += face_area / 3.0;
      normal_sum[v] += face_area * normal;
      shape.quadric[v] += Sqem::plane(input.points[v], normal, face_area / 3.0);
      edges.emplace_back(v, f[(corner + 1) % 3]);
    }
  }
  shape.normals.resize(n);
  for (int v = 0; v < n; ++v) {
    // Opposite faces at a non-manifold vertex can cancel out; any unit vector beats NaN there.
    const double length = normal_sum[v].norm();
    shape.normals[v] = length > 0.0 ? Vec3(normal_sum[v] / length) : Vec3::UnitZ();
  }
  set_neighbour_graph(shape, std::move(edges));
}

// Joins the pieces of the graph `edges` over `points` by the shortest of the pairs among each
// point's kJoiningNeighbours nearest that connect two pieces (Kruskal over those pairs, after the
// graph's own edges): the minimum spanning forest's bridges. A connected graph gains nothing and
// costs one pass over its edges.
void add_bridges(const std::vector<Vec3>& points, const KdTree& tree,
                 std::vector<std::pair<int, int>>& edges) {
  const int n = static_cast<int>(points.size());
  internal::DisjointSets pieces(n);
  for (const auto& [a, b] : edges) pieces.unite(a, b);
  if (pieces.sets() == 1) return;
  std::vector<std::tuple<double, int, int>> candidates;
  std::vector<int> nearest;
  std::vector<double> squared;
  for (int v = 0; v < n; ++v) {
    tree.k_nearest(points[v], internal::kJoiningNeighbours + 1, nearest, squared);
    for (std::size_t i = 1; i < nearest.size(); ++i)
      if (pieces.find(v) != pieces.find(nearest[i]))
        candidates.emplace_back(squared[i], v, nearest[i]);
  }
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [length, a, b] : candidates)
    if (pieces.unite(a, b)) edges.emplace_back(a, b);
}

void build_cloud_attributes(const SurfaceInput& input, const ShapeOptions& options, Shape& shape) {
  const int n = shape.size();
  if (!input.has_normals()) throw InvalidInput("a point cloud needs normals (estimate them first)");
  if (n <= options.k)
    throw InvalidInput("too few points (" + std::to_string(n) +
                       ") for k=" + std::to_string(options.k));
  for (std::size_t v = 0; v < input.normals.size(); ++v)
    if (!input.normals[v].allFinite() || !(input.normals[v].squaredNorm() > 0.0))
      throw InvalidInput("point " + std::to_string(v) +
                         " has no valid normal (fill_missing_normals first)");
  shape.normals = input.normals;
  const KdTree tree(shape.points);
  // Support area (Zhao et al. 2023): squared mean distance to the K nearest neighbours.
  const int area_k = std::max(6, options.k);
  std::vector<std::vector<int>> knn(n);
  shape.area.assign(n, 0.0);
#pragma omp parallel
  {
    std::vector<int> indices;
    std::vector<double> distances;
#pragma omp for schedule(static)
    for (int v = 0; v < n; ++v) {
      tree.k_nearest(shape.points[v], area_k + 1, indices, distances);
      double mean = 0.0;
      for (std::size_t i = 1; i < distances.size(); ++i) mean += std::sqrt(distances[i]);
      mean /= static_cast<double>(distances.size() - 1);
      shape.area[v] = mean * mean;
      // The k nearest including v itself: the support of the diffused quadric (eq. 5).
      knn[v].assign(indices.begin(), indices.begin() + std::min<int>(options.k, indices.size()));
    }
  }
  shape.quadric.assign(n, Sqem{});
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<std::size_t>(n) * options.k);
  for (int v = 0; v < n; ++v) {
    for (int j : knn[v]) {
      shape.quadric[v] += Sqem::plane(shape.points[j], shape.normals[j], shape.area[j] / options.k);
      if (j != v) edges.emplace_back(v, j);
    }
  }
  add_bridges(shape.points, tree, edges);
  set_neighbour_graph(shape, std::move(edges));
}

// Vertices per block: smaller blocks bound tighter but cost more sphere tests per vertex.
constexpr int kBlockSize = 32;

// Splits vertices[begin, end) at the median of its widest axis until at most kBlockSize remain.
void split_blocks(const std::vector<Vec3>& points, int begin, int end, VertexBlocks& blocks) {
  auto first = blocks.vertices.begin() + begin;
  auto last = blocks.vertices.begin() + end;
  Vec3 low = points[*first], high = low;
  for (auto it = first; it != last; ++it) {
    low = low.cwiseMin(points[*it]);
    high = high.cwiseMax(points[*it]);
  }
  if (end - begin <= kBlockSize) {
    std::sort(first, last);  // ascending ids: closer in memory
    const Vec3 center = 0.5 * (low + high);
    double radius = 0.0;
    for (auto it = first; it != last; ++it)
      radius = std::max(radius, (points[*it] - center).norm());
    blocks.offsets.push_back(end);
    blocks.centers.push_back(center);
    blocks.radii.push_back(radius);
    return;
  }
  int axis;
  (high - low).maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(first, blocks.vertices.begin() + middle, last,
                   [&](int a, int b) { return points[a][axis] < points[b][axis]; });
  split_blocks(points, begin, middle, blocks);
  split_blocks(points, middle, end, blocks);
}

VertexBlocks build_blocks(const std::vector<Vec3>& points) {
  VertexBlocks blocks;
  blocks.vertices.resize(points.size());
  std::iota(blocks.vertices.begin(), blocks.vertices.end(), 0);
  blocks.offsets.push_back(0);
  split_blocks(points, 0, static_cast<int>(points.size()), blocks);
  return blocks;
}

}  // namespace

Shape build_shape(const SurfaceInput& input, const ShapeOptions& options) {
  options.validate();
  if (input.points.empty()) throw InvalidInput("the shape has no points");
  Shape shape;
  shape.points = input.points;
  if (!input.density.empty()) check_density(input.density, input.points.size());
  shape.set_density(input.density);
  shape.is_mesh = input.is_mesh();
  shape.diagonal = diagonal_of(bounding_box(input.points));
  if (!(shape.diagonal > 0.0)) throw InvalidInput("all points coincide");
  if (shape.is_mesh)
    build_mesh_attributes(input, shape);
  else
    build_cloud_attributes(input, options, shape);
  shape.blocks = build_blocks(shape.points);
  for (double a : shape.area) shape.total_area += a;
  if (!(shape.total_area > 0.0)) throw InvalidInput("the shape has zero area");
  return shape;
}

Shape coarsen_shape(const Shape& shape, std::size_t budget) {
  // The dominant axis and sign of each normal: opposite sides of a thin part fall apart.
  std::vector<std::uint8_t> direction(shape.size());
  for (int v = 0; v < shape.size(); ++v) {
    int axis = 0;
    shape.normals[v].cwiseAbs().maxCoeff(&axis);
    direction[v] = static_cast<std::uint8_t>(2 * axis + (shape.normals[v][axis] < 0.0 ? 1 : 0));
  }
  const Subsample cells = subsample(shape.points, budget, direction);
  Shape coarse;
  const std::size_t count = cells.kept.size();
  coarse.points.reserve(count);
  for (int v : cells.kept) {
    coarse.points.push_back(shape.points[v]);
    coarse.normals.push_back(shape.normals[v]);
  }
  coarse.area.assign(count, 0.0);
  coarse.quadric.assign(count, Sqem());
  std::vector<internal::DensityMean> density(shape.density.empty() ? 0 : count);
  std::vector<std::pair<int, int>> pairs;
  for (int v = 0; v < shape.size(); ++v) {
    const int cell = cells.representative[v];
    coarse.area[cell] += shape.area[v];
    if (!density.empty()) density[cell].add(shape.density[v], shape.area[v]);
    coarse.quadric[cell] += shape.quadric[v];
    for (int k = shape.neighbour_offsets[v]; k < shape.neighbour_offsets[v + 1]; ++k) {
      const int other = cells.representative[shape.neighbours[k]];
      if (other > cell) pairs.emplace_back(cell, other);  // the graph is symmetric
    }
  }
  std::vector<double> cell_density;
  for (const internal::DensityMean& mean : density) cell_density.push_back(mean.value());
  coarse.set_density(std::move(cell_density));
  set_neighbour_graph(coarse, pairs);
  coarse.blocks = build_blocks(coarse.points);
  coarse.is_mesh = shape.is_mesh;
  coarse.diagonal = shape.diagonal;
  coarse.total_area = shape.total_area;
  return coarse;
}

}  // namespace vmas
