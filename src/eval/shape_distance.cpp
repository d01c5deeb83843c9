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

ShapeDistance::ShapeDistance(const SurfaceInput& shape) : shape_(shape) {
  if (!shape.is_mesh()) {
    points_.emplace(shape.points);
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

}  // namespace internal
}  // namespace vmas
