#include "prepare/noise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/kdtree.hpp"
#include "core/quadric_fit.hpp"
#include "pcl_backend/mls.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace {

// Median of |x| for a standard normal x: a robust deviation is a median distance over this.
constexpr double kHalfNormalMedian = 0.6745;

// RMS distance of `points[indices]` to their quadric (fit_quadric), with the six fitted
// coefficients taken out of the degrees of freedom. NaN when the neighbourhood is degenerate.
double quadric_residual(const std::vector<Vec3>& points, const std::vector<int>& indices) {
  const internal::QuadricFit quadric = internal::fit_quadric(points, indices);
  if (!quadric.valid) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(quadric.residual_squares / (static_cast<double>(indices.size()) - 6.0));
}

}  // namespace

NoiseEstimate estimate_noise(const std::vector<Vec3>& points) {
  constexpr int kMaxNeighbours = 2048;
  constexpr double kRadiusInResiduals = 3.0;
  // The noise of a point does not depend on how many others there are: the fits run on an even
  // subset, so that big clouds cost no more and need no bigger neighbourhoods.
  constexpr int kSubset = 10'000;
  // Query points: enough for a stable median, fewer for the large neighbourhoods.
  constexpr long kQueryNeighbours = 500'000, kMinQueries = 500, kMaxQueries = 4000;
  const int count = static_cast<int>(points.size());
  if (count < kFewestNoiseNeighbours)
    throw InvalidInput("too few points (" + std::to_string(count) + ") to estimate the noise");
  NoiseEstimate estimate;
  const KdTree tree(points);
  estimate.spacing = median_spacing(tree, points, std::max(1, count / kSubset));

  std::vector<Vec3> subset;
  for (int i = 0; i < count; i += std::max(1, count / kSubset)) subset.push_back(points[i]);
  const int subset_count = static_cast<int>(subset.size());
  const KdTree subset_tree(subset);
  for (int k = kFewestNoiseNeighbours; k <= kMaxNeighbours; k *= 2) {
    const int width = std::min(k, subset_count);
    const long queries_wanted = std::clamp(kQueryNeighbours / width, kMinQueries, kMaxQueries);
    const int stride = std::max<long>(1, subset_count / queries_wanted);
    std::vector<int> queries;
    for (int i = 0; i < subset_count; i += stride) queries.push_back(i);
    const int query_count = static_cast<int>(queries.size());
    std::vector<double> residuals(query_count), radii(query_count);
#pragma omp parallel
    {
      std::vector<int> neighbours;
      std::vector<double> distances;
#pragma omp for schedule(static)
      for (int q = 0; q < query_count; ++q) {
        subset_tree.k_nearest(subset[queries[q]], width, neighbours, distances);
        residuals[q] = quadric_residual(subset, neighbours);
        radii[q] = std::sqrt(distances.back());
      }
    }
    residuals.erase(std::remove_if(residuals.begin(), residuals.end(),
                                   [](double r) { return !std::isfinite(r); }),
                    residuals.end());
    estimate.sigma = median(residuals);
    estimate.neighbours = width;
    if (median(radii) >= kRadiusInResiduals * estimate.sigma || width == subset_count) break;
  }
  return estimate;
}

void DenoiseOptions::validate() const {
  if (!(clean_fraction_of_spacing >= 0.0 && clean_fraction_of_spacing <= 100.0))
    throw InvalidOption("clean_fraction_of_spacing", "must be in [0, 100]");
  if (!(mls_radius_in_sigmas > 0.0 && mls_radius_in_sigmas <= 100.0))
    throw InvalidOption("mls_radius_in_sigmas", "must be in (0, 100] smoothing scales");
  if (outlier_k < 2 || outlier_k > 200)
    throw InvalidOption("outlier_k",
                        "must be between 2 and 200 (got " + std::to_string(outlier_k) + ")");
  if (!(outlier_deviations > 0.0)) throw InvalidOption("outlier_deviations", "must be positive");
}

bool is_noisy(const NoiseEstimate& noise, const DenoiseOptions& options) {
  return noise.sigma > options.clean_fraction_of_spacing * noise.spacing;
}


double mls_deviation(const std::vector<Vec3>& points, double radius, int samples) {
  if (samples < 1) throw std::logic_error("mls_deviation: needs at least one sample");
  if (points.empty()) return 0.0;
  std::vector<int> measured;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / samples);
  for (std::size_t i = 0; i < points.size(); i += stride) measured.push_back(static_cast<int>(i));
  const internal::MlsSurfaces surfaces(points, radius, &measured);
  std::vector<double> distances(measured.size(), 0.0);  // a point without a fit stays: 0
  for (std::size_t k = 0; k < measured.size(); ++k) {
    Vec3 projected, normal;
    if (surfaces.project(points[measured[k]], projected, normal))
      distances[k] = (points[measured[k]] - projected).norm();
  }
  return median(std::move(distances)) / kHalfNormalMedian;
}

}  // namespace vmas
