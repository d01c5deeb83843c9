#include "prepare/outliers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/kdtree.hpp"
#include "core/principal_axes.hpp"
#include "core/quadric_fit.hpp"
#include "pcl_backend/cloud_search.hpp"

namespace vmas {
namespace {

// The inliers among `candidates` by pcl::StatisticalOutlierRemoval's rule, computed as it does
// (float distances, the same sums), but with vmas's searcher (the same neighbours): the filter keeps its own
// searcher private. A point whose mean distance to its k nearest neighbours in the whole cloud
// exceeds the mean of those by `deviations` standard deviations is an outlier.
std::vector<int> statistical_inliers(const internal::FloatCloudSearch& search,
                                     const std::vector<Vec3>& points,
                                     const std::vector<int>& candidates, int k, double deviations) {
  const int searched = k + 1;  // the point itself comes first
  std::vector<float> mean_distance(candidates.size(), 0.0f);
  const auto count = static_cast<std::ptrdiff_t>(candidates.size());
  int measured = 0;
#pragma omp parallel reduction(+ : measured)
  {
    std::vector<int> neighbours(searched);
    std::vector<float> squared(searched);
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      if (search.nearest(points[candidates[i]], searched, neighbours, squared) == 0) continue;
      double sum = 0.0;
      for (int j = 1; j < searched; ++j) sum += std::sqrt(squared[j]);
      mean_distance[i] = static_cast<float>(sum / k);
      ++measured;
    }
  }
  double sum = 0.0, squares = 0.0;
  for (float d : mean_distance) {
    sum += d;
    squares += d * d;  // in float, as PCL does
  }
  const double mean = sum / measured;
  const double deviation = std::sqrt((squares - sum * sum / measured) / (measured - 1.0));
  const double threshold = mean + deviations * deviation;
  std::vector<int> inliers;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (!(mean_distance[i] > threshold)) inliers.push_back(candidates[i]);
  return inliers;
}

}  // namespace

std::vector<int> inlier_indices(const std::vector<Vec3>& points, const DenoiseOptions& options) {
  options.validate();
  // Gross outliers inflate the deviation of the neighbour distances that the filter measures
  // them against, so that those nearer the surface survive a pass; passes repeat while they
  // remove a noticeable share. A clean cloud stops after one. A first pass that flags a large
  // share has found uneven density, not strays (the merged bunny scan: 3 %, its sparse parts;
  // dropping them cost 0.5 points of ε): the cloud is kept whole.
  constexpr int kMaxPasses = 4;
  constexpr double kNoticeable = 0.005, kLarge = 0.02;
  std::vector<int> kept(points.size());
  std::iota(kept.begin(), kept.end(), 0);
  const internal::FloatCloudSearch search(points, internal::centroid_of(points), false);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    if (static_cast<int>(kept.size()) <= 2 * options.outlier_k) break;
    const std::vector<int> inliers =
        statistical_inliers(search, points, kept, options.outlier_k, options.outlier_deviations);
    const std::size_t removed = kept.size() - inliers.size();
    kept = inliers;
    const double share = static_cast<double>(removed) / static_cast<double>(points.size());
    if (pass == 0 && share > kLarge) {
      kept.resize(points.size());
      std::iota(kept.begin(), kept.end(), 0);
      break;
    }
    if (share < kNoticeable || share > kLarge) break;
  }
  return kept;
}

namespace {

// A flagged point stays when it continues the sampling of its nearest neighbour j that is kept,
// only more sparsely: within kNearReach × m_j (j's mean distance to its neighbours), or within
// kFarReach × m_j and kOffPlane × m_j of the surface through j's neighbourhood (its quadric: at
// a curved tip a plane would leave the sampling's own sparse points off it). A stray's nearest
// kept point is the surface below it, and it lies off that surface.
constexpr double kNearReach = 1.0, kFarReach = 2.0, kOffPlane = 0.3;
// A sparse part is kept from its edge inwards (its inner points may have only flagged
// neighbours), for at most this many rounds; strays lie several spacings apart and never
// continue one another.
constexpr int kSparseRounds = 8;
// In a clean sampling nearly every flagged point continues it (at least 97 % on 48 clean clouds
// of 2 000-50 000 points); in one with scattered strays most do not (at most 28 % with 1 %
// uniform strays), and the few that do are strays near the surface as often as sparse parts:
// there a flagged point stays only when it lies on the quadric, however near (a thin tip's few
// points, which the vessel with 1 % strays lost: ε 1.08 % against 0.64 %).
constexpr double kScatteredShare = 0.5;

}  // namespace

std::vector<int> with_sparse_parts(const std::vector<Vec3>& points, const std::vector<int>& inliers,
                                   const DenoiseOptions& options) {
  options.validate();
  const int count = static_cast<int>(points.size());
  const int k = options.outlier_k;
  if (inliers.size() == points.size() || count <= k) return inliers;
  const KdTree tree(points);
  // A point's k nearest others, looked up once and only for the points the rule needs.
  std::vector<std::vector<int>> neighbours(count);
  std::vector<double> squared;
  const auto neighbours_of = [&](int p) -> const std::vector<int>& {
    if (neighbours[p].empty()) {
      tree.k_nearest(points[p], k + 1, neighbours[p], squared);
      neighbours[p].erase(neighbours[p].begin());  // the point itself
    }
    return neighbours[p];
  };
  // Spacing of the sampling a point belongs to: its own mean neighbour distance if it is kept,
  // that of the point it continues if it is kept as sparse; NaN while it is flagged.
  std::vector<double> spacing(count, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> kept(count, 0);
  for (int i : inliers) kept[i] = 1;
  const auto spacing_of = [&](int j) {
    if (kept[j] && std::isnan(spacing[j])) {
      double sum = 0.0;
      for (int n : neighbours_of(j)) sum += (points[n] - points[j]).norm();
      spacing[j] = sum / k;
    }
    return spacing[j];
  };
  // `on_surface_only`: a flagged point near its kept neighbour must lie on the quadric too.
  const auto continues = [&](int p, int j, double reach, bool on_surface_only) {
    const double gap = (points[p] - points[j]).norm();
    if (gap <= kNearReach * reach && !on_surface_only) return true;
    if (gap > kFarReach * reach) return false;
    std::vector<int> around = neighbours_of(j);
    around.push_back(j);
    const internal::QuadricFit surface = internal::fit_quadric(points, around);
    return surface.valid && surface.offset(points[p]) <= kOffPlane * reach;
  };
  const auto grow = [&](bool on_surface_only) {
    for (int p = 0; p < count; ++p)
      if (!kept[p]) spacing[p] = std::numeric_limits<double>::quiet_NaN();
    std::vector<int> grown_points = inliers;
    for (int round = 0; round < kSparseRounds; ++round) {
      bool grown = false;
      for (int p = 0; p < count; ++p) {
        if (kept[p] || !std::isnan(spacing[p])) continue;
        for (int j : neighbours_of(p)) {
          const double reach = spacing_of(j);
          if (std::isnan(reach)) continue;  // flagged too: the next nearest
          if (continues(p, j, reach, on_surface_only)) {
            spacing[p] = reach;
            grown_points.push_back(p);
            grown = true;
          }
          break;  // only the nearest point that is not flagged counts
        }
      }
      if (!grown) break;
    }
    return grown_points;
  };
  std::vector<int> result = grow(false);
  const std::size_t flagged = points.size() - inliers.size();
  const std::size_t continuing = result.size() - inliers.size();
  if (static_cast<double>(flagged - continuing) > kScatteredShare * static_cast<double>(flagged))
    result = grow(true);
  std::sort(result.begin(), result.end());
  return result;
}

}  // namespace vmas
