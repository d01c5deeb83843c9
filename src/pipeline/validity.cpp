#include "pipeline/validity.hpp"

#include <cmath>

namespace vmas {
namespace {

// A centre whose winding number is at most this lies outside the solid.
constexpr double kInside = 0.5;
// A radius this far (fraction of the diagonal) from the distance to the surface is no medial
// ball's: well above a cloud's spacing, by which the distance to its nearest point overstates
// the distance to the surface it samples.
constexpr double kRadiusTolerance = 0.01;

}  // namespace

InvalidSpheres invalid_spheres(const std::vector<Sphere>& spheres, const MedialProjector& projector,
                               const Evaluator& evaluator, double diagonal) {
  InvalidSpheres invalid;
  invalid.checked = true;
  std::vector<Vec3> centers;
  centers.reserve(spheres.size());
  for (const Sphere& s : spheres) centers.push_back(s.center);
  const std::vector<double> distance = evaluator.distances_to_shape(centers);
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    invalid.outside += projector.winding_number(spheres[i].center) <= kInside;
    invalid.radius_off += std::abs(spheres[i].radius - distance[i]) > kRadiusTolerance * diagonal;
  }
  return invalid;
}

std::vector<std::array<int, 3>> where_tunnels_fit(std::vector<std::array<int, 3>> triangles,
                                                  const std::vector<Sphere>& spheres,
                                                  const MedialProjector& projector,
                                                  const Evaluator& evaluator, double depth) {
  std::vector<Vec3> centroids;
  centroids.reserve(triangles.size());
  for (const auto& [a, b, c] : triangles)
    centroids.push_back((spheres[a].center + spheres[b].center + spheres[c].center) / 3.0);
  const std::vector<double> distance = evaluator.distances_to_shape(centroids);
  std::size_t kept = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (distance[t] <= depth || projector.winding_number(centroids[t]) <= kInside)
      triangles[kept++] = triangles[t];
  triangles.resize(kept);
  return triangles;
}

std::size_t turn_inside_out_normals(SurfaceInput& surface, PrepareReport& report,
                                    const Shape& shape) {
  if (surface.is_mesh() || !report.smoothed() || !report.normals_estimated ||
      !report.holes.empty())
    return 0;
  const std::vector<int> turned = MedialProjector::inside_out(shape);
  for (int v : turned) surface.normals[v] = -surface.normals[v];
  return report.normals_turned = turned.size();
}

}  // namespace vmas
