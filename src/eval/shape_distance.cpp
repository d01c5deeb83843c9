#include "eval/shape_distance.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "vmas/error.hpp"

namespace vmas {
namespace internal {

void check_shape(const SurfaceInput& shape) {
  if (shape.points.empty()) throw InvalidInput("shape has no point");
  const int n = static_cast<int>(shape.points.size());
  for (std::size_t f = 0; f < shape.faces.size(); ++f) {
    for (int v : shape.faces[f]) {
      if (v < 0 || v >= n) {
        throw InvalidInput("shape face " + std::to_string(f) + ": vertex index " +
                           std::to_string(v) + " out of range");
      }
    }
  }
}

std::vector<Vec3> surface_samples(const SurfaceInput& shape, int count, unsigned seed) {
  std::vector<Vec3> samples = shape.points;
  if (!shape.is_mesh() || count <= 0) return samples;
  std::vector<double> cumulative_area;
  double total = 0.0;
  for (const auto& f : shape.faces) {
    const Vec3& a = shape.points[f[0]];
    total += 0.5 * (shape.points[f[1]] - a).cross(shape.points[f[2]] - a).norm();
    cumulative_area.push_back(total);
  }
  if (!(total > 0.0)) return samples;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const double pick = uniform(rng) * total;
    const auto face =
        std::min(static_cast<std::size_t>(
                     std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                     cumulative_area.begin()),
                 shape.faces.size() - 1);
    const auto& f = shape.faces[face];
    const double r = std::sqrt(uniform(rng)), t = uniform(rng);
    samples.push_back((1.0 - r) * shape.points[f[0]] + r * (1.0 - t) * shape.points[f[1]] +
                      r * t * shape.points[f[2]]);
  }
  return samples;
}

namespace {

// A point's disc reaches its this-th nearest neighbour: wide enough to close the gaps of a
// random sampling (the mean spacing is about its 1st-2nd neighbour), narrow enough that its
// departure from a curved surface (radius² / 2 × curvature) stays far below the spacing.
constexpr int kDiscNeighbours = 8;

}  // namespace

ShapeDistance::ShapeDistance(const SurfaceInput& shape, bool discs,
                             const std::vector<Vec3>& lid_points)
    : shape_(shape) {
  if (!lid_points.empty()) lid_points_.emplace(lid_points);
  if (!shape.is_mesh()) {
    points_.emplace(shape.points);
    const bool normals = shape.normals.size() == shape.points.size();
    if (!discs || !normals || shape.points.size() <= kDiscNeighbours) return;
    disc_radius_.resize(shape.points.size());
    const auto count = static_cast<std::ptrdiff_t>(shape.points.size());
#pragma omp parallel
    {
      std::vector<int> neighbours;
      std::vector<double> squared;
#pragma omp for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        points_->k_nearest(shape.points[i], kDiscNeighbours + 1, neighbours, squared);
        disc_radius_[i] = std::sqrt(squared.back());
      }
    }
    return;
  }
  boxes_.reserve(shape.faces.size());
  for (const auto& f : shape.faces) {
    boxes_.push_back(Box(shape.points[f[0]]).extend(shape.points[f[1]]).extend(shape.points[f[2]]));
  }
  triangles_.emplace(boxes_);
}

std::vector<double> ShapeDistance::operator()(const std::vector<Vec3>& queries,
                                              double stop_below) const {
  std::vector<double> distances(queries.size());
  const auto count = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel
  {
    int near_face = -1;  // neighbouring queries are near the same face: it is tried first
#pragma omp for schedule(dynamic, 4096)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      distances[i] = distance(queries[i], stop_below, near_face);
  }
  return distances;
}

double ShapeDistance::distance(const Vec3& q, double stop_below, int& near_face) const {
  const double to_input = input_distance(q, stop_below, near_face);
  if (!lid_points_) return to_input;
  double squared = 0.0;
  lid_points_->nearest(q, &squared);
  return std::min(to_input, std::sqrt(squared));
}

double ShapeDistance::input_distance(const Vec3& q, double stop_below, int& near_face) const {
  if (!disc_radius_.empty()) return disc_distance(q);
  if (points_) {
    double squared = 0.0;
    points_->nearest(q, &squared);
    return std::sqrt(squared);
  }
  return triangles_->nearest(
      q,
      [&](int face) {
        const auto& f = shape_.faces[face];
        return point_triangle_distance(q, shape_.points[f[0]], shape_.points[f[1]],
                                       shape_.points[f[2]]);
      },
      stop_below, &near_face);
}

// The least distance from `q` to the discs of its nearest points: within a disc's radius of its
// point, the distance across its tangent plane.
double ShapeDistance::disc_distance(const Vec3& q) const {
  thread_local std::vector<int> neighbours;
  thread_local std::vector<double> squared;
  points_->k_nearest(q, kDiscNeighbours, neighbours, squared);
  double best = kInfinity;
  for (int i : neighbours) {
    const Vec3 offset = q - shape_.points[i];
    const Vec3& normal = shape_.normals[i];
    double distance = offset.norm();
    if (normal.allFinite()) {
      const double across = normal.dot(offset);
      const double along = std::max(0.0, (offset - across * normal).norm() - disc_radius_[i]);
      distance = std::sqrt(across * across + along * along);
    }
    best = std::min(best, distance);
  }
  return best;
}

}  // namespace internal
}  // namespace vmas
