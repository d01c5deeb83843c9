#include "prepare/visibility.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "core/sphere_lattice.hpp"

namespace vmas {

namespace {

// Views: enough that every outward-facing patch of a shape with moderate concavities is seen
// head-on by a few of them.
constexpr int kViews = 64;

}  // namespace

std::vector<double> visibility_votes(const std::vector<Vec3>& points,
                                     const std::vector<Vec3>& normals, double pixel) {
  const std::size_t count = points.size();
  std::vector<double> votes(count, 0.0);
  if (count == 0) return votes;
  // At most about 4 pixels per point in a view, whatever `pixel` says (duplicates, a spacing of 0).
  pixel = std::max(
      pixel, bounding_box(points).sizes().norm() / (2.0 * std::sqrt(static_cast<double>(count))));
  if (!(pixel > 0.0)) return votes;
  std::vector<int> seen(count, 0);
  std::vector<std::ptrdiff_t> cell(count);
  std::vector<double> depth(count);
  for (int view = 0; view < kViews; ++view) {
    const Vec3 d = internal::fibonacci_direction(view, kViews);
    const Vec3 u = d.unitOrthogonal();
    const Vec3 v = d.cross(u);
    double u_min = std::numeric_limits<double>::infinity(), v_min = u_min;
    double u_max = -u_min, v_max = -u_min;
    for (const Vec3& p : points) {
      u_min = std::min(u_min, p.dot(u));
      u_max = std::max(u_max, p.dot(u));
      v_min = std::min(v_min, p.dot(v));
      v_max = std::max(v_max, p.dot(v));
    }
    const auto columns = static_cast<std::ptrdiff_t>((u_max - u_min) / pixel) + 1;
    const auto rows = static_cast<std::ptrdiff_t>((v_max - v_min) / pixel) + 1;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(count); ++i) {
      const Vec3& p = points[i];
      const auto column =
          std::min(static_cast<std::ptrdiff_t>((p.dot(u) - u_min) / pixel), columns - 1);
      const auto row = std::min(static_cast<std::ptrdiff_t>((p.dot(v) - v_min) / pixel), rows - 1);
      cell[i] = row * columns + column;
      depth[i] = p.dot(d);
    }
    std::vector<double> front(static_cast<std::size_t>(columns * rows),
                              std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < count; ++i) front[cell[i]] = std::min(front[cell[i]], depth[i]);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(count); ++i) {
      if (depth[i] > front[cell[i]] + pixel) continue;
      votes[i] -= normals[i].dot(d);
      ++seen[i];
    }
  }
  for (std::size_t i = 0; i < count; ++i)
    if (seen[i] > 0) votes[i] /= seen[i];
  return votes;
}

}  // namespace vmas
