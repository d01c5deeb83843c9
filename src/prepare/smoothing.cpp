#include "prepare/smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/principal_axes.hpp"
#include "pcl_backend/cloud_search.hpp"
#include "pcl_backend/mls.hpp"

namespace vmas {
namespace {

// restore_smoothing_bias: residuals are averaged over the points within this fraction of the
// smoothing's support radius, ...
constexpr double kBiasRadiusInSupports = 0.5;
// ... at least this many (their noise falls to a tenth), of an even subset of every
// (n / this)-th point (8 000 to 16 000 points; all below 16 000).
constexpr std::size_t kBiasNeighbours = 128, kBiasReferencePoints = 8000;
// ... and a point takes a blend of the figures of this many nearest of the subset.
constexpr std::size_t kBiasBlended = 4;

}  // namespace

std::vector<Vec3> smooth_mls(std::vector<Vec3>& points, double radius) {
  const internal::MlsSurfaces surfaces(points, radius, nullptr);
  std::vector<Vec3> normals(points.size(),
                            Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  const int count = static_cast<int>(points.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < count; ++i) {
    Vec3 projected, normal;
    if (!surfaces.project(points[i], projected, normal)) continue;
    points[i] = projected;
    normals[i] = normal;
  }
  return normals;
}

void restore_smoothing_bias(std::vector<Vec3>& smoothed, const std::vector<Vec3>& normals,
                            const std::vector<Vec3>& raw, double support) {
  const double radius = kBiasRadiusInSupports * support;
  if (smoothed.empty() || !(radius > 0.0)) return;
  const Vec3 centroid = internal::centroid_of(smoothed);
  // The bias varies over the smoothing's support, not from point to point: it is measured around
  // an even subset of the points, and each point takes a blend of the figures of its nearest.
  const std::size_t stride = std::max<std::size_t>(1, smoothed.size() / kBiasReferencePoints);
  std::vector<Vec3> reference, residuals;
  for (std::size_t i = 0; i < smoothed.size(); i += stride) {
    reference.push_back(smoothed[i]);
    residuals.push_back(raw[i] - smoothed[i]);
  }
  const internal::FloatCloudSearch search(reference, centroid, true);
  const int least_neighbours = static_cast<int>(std::min(kBiasNeighbours, reference.size()));
  std::vector<Vec3> mean_residual(reference.size(), Vec3::Zero());
  const auto references = static_cast<std::ptrdiff_t>(reference.size());
#pragma omp parallel
  {
    std::vector<int> around;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t r = 0; r < references; ++r) {
      if (search.within(reference[r], radius, around, squared) < least_neighbours)
        search.nearest(reference[r], least_neighbours, around, squared);
      for (int j : around) mean_residual[r] += residuals[j];
      mean_residual[r] /= static_cast<double>(around.size());
    }
  }
  const auto count = static_cast<std::ptrdiff_t>(smoothed.size());
  const int blend_count = static_cast<int>(std::min(kBiasBlended, reference.size()));
#pragma omp parallel
  {
    std::vector<int> nearest;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const Vec3& normal = normals[i];
      if (!normal.allFinite()) continue;
      search.nearest(smoothed[i], blend_count, nearest, squared);
      // Inverse-distance weights: a change of the nearest reference makes no step, only a change
      // of the farthest of the few blended, where its weight is least.
      Vec3 bias = Vec3::Zero();
      double weight_sum = 0.0;
      for (std::size_t c = 0; c < nearest.size(); ++c) {
        const double weight = 1.0 / (std::sqrt(static_cast<double>(squared[c])) + 1e-12 * radius);
        bias += weight * mean_residual[nearest[c]];
        weight_sum += weight;
      }
      smoothed[i] += (bias / weight_sum).dot(normal) * normal;
    }
  }
}


double smooth_mesh(std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces,
                   int steps) {
  const std::vector<Vec3> noisy = points;
  const int count = static_cast<int>(points.size());
  // Each vertex's edge neighbours, once each (CSR).
  std::vector<std::pair<int, int>> edges;
  edges.reserve(6 * faces.size());
  for (const auto& face : faces)
    for (int c = 0; c < 3; ++c) {
      edges.emplace_back(face[c], face[(c + 1) % 3]);
      edges.emplace_back(face[(c + 1) % 3], face[c]);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<int> offsets(count + 1, 0);
  for (const auto& edge : edges) ++offsets[edge.first + 1];
  for (int v = 0; v < count; ++v) offsets[v + 1] += offsets[v];

  constexpr double kLambda = 0.5, kMu = -0.53;
  std::vector<Vec3> moved(points.size());
  const auto pass = [&](double weight) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < count; ++v) {
      const int first = offsets[v], last = offsets[v + 1];
      if (first == last) {
        moved[v] = points[v];
        continue;
      }
      Vec3 mean = Vec3::Zero();
      for (int e = first; e < last; ++e) mean += points[edges[e].second];
      mean /= static_cast<double>(last - first);
      moved[v] = points[v] + weight * (mean - points[v]);
    }
    points.swap(moved);
  };
  for (int step = 0; step < steps; ++step) {
    pass(kLambda);
    pass(kMu);
  }
  // How far the vertices moved across the smoothed surface (area-weighted vertex normals).
  std::vector<Vec3> normals(points.size(), Vec3::Zero());
  for (const auto& face : faces) {
    const Vec3 area = (points[face[1]] - points[face[0]]).cross(points[face[2]] - points[face[0]]);
    for (int v : face) normals[v] += area;
  }
  double squares = 0.0;
  int moved_count = 0;
  for (int v = 0; v < count; ++v) {
    const double length = normals[v].norm();
    if (!(length > 0.0)) continue;
    squares += std::pow((noisy[v] - points[v]).dot(normals[v]) / length, 2);
    ++moved_count;
  }
  return moved_count > 0 ? std::sqrt(squares / moved_count) : 0.0;
}

}  // namespace vmas
