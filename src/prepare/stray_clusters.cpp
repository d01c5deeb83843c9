#include "prepare/stray_clusters.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <optional>

#include "core/disjoint_sets.hpp"
#include "core/kdtree.hpp"
#include "prepare/noise.hpp"

namespace vmas {
namespace {

// Two points are joined within this many of the cloud's median reach (the distance to the 16th
// nearest neighbour): a gap of twice that (about 5 spacings of a regular grid, 10 nearest-
// neighbour distances of a random sampling, whose widest natural gaps among 100 000 points are
// about 4) parts a cluster ...
constexpr double kGapInReaches = 2.0;
// ... or within this many spacings of the sampling around either: the largest nearest-neighbour
// distance among its 16 nearest. A part sampled more sparsely (a tail, an under-scanned base)
// is joined by its own spacing, while a lone stray's neighbours are the object's points, whose
// spacing is the object's: it cannot reach out by its own emptiness.
constexpr double kGapInSpacings = 2.0;
// A piece within this many noise deviations of the object is the noise's tail, not a cluster
// (Gaussian noise of 30 000 points reaches about 4.3 deviations from the surface).
constexpr double kNoiseReach = 5.0;
// A piece holding at most this share of the points is a stray cluster ...
constexpr double kMaxClusterShare = 0.01;
// ... unless such pieces together hold more than this: then the data is in many pieces.
constexpr double kMaxStrayShare = 0.1;

double median_of(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

StrayClusterSplit without_stray_clusters(const std::vector<Vec3>& points,
                                         const std::vector<std::size_t>& weights, double noise) {
  return without_stray_clusters(
      points, internal::k_nearest_all(points, internal::kJoiningNeighbours), weights, noise);
}

StrayClusterSplit without_stray_clusters(const std::vector<Vec3>& points,
                                         const internal::Neighbourhoods& rows,
                                         const std::vector<std::size_t>& weights, double noise) {
  StrayClusterSplit split;
  const int count = static_cast<int>(points.size());
  split.kept.resize(count);
  std::iota(split.kept.begin(), split.kept.end(), 0);
  if (count <= internal::kJoiningNeighbours + 1) return split;
  std::vector<double> reach(count), nearest(count), spacing(count, 0.0);
  for (int i = 0; i < count; ++i) {
    reach[i] = (points[rows.row(i)[rows.width - 1]] - points[i]).norm();
    nearest[i] = (points[rows.row(i)[1]] - points[i]).norm();
  }
  for (int i = 0; i < count; ++i)
    for (int c = 1; c < rows.width; ++c) spacing[i] = std::max(spacing[i], nearest[rows.row(i)[c]]);
  const double gap = kGapInReaches * median_of(std::move(reach));
  if (!(gap > 0.0)) return split;
  const auto joined = [&](int a, int b) {
    return (points[a] - points[b]).norm() <=
           std::max(gap, kGapInSpacings * std::max(spacing[a], spacing[b]));
  };
  internal::DisjointSets pieces(count);
  for (int i = 0; i < count; ++i)
    for (int c = 1; c < rows.width; ++c)
      if (joined(i, rows.row(i)[c])) pieces.unite(i, rows.row(i)[c]);

  const auto weight = [&](int i) { return weights.empty() ? std::size_t{1} : weights[i]; };
  std::vector<std::size_t> piece_weight(count, 0);
  std::size_t total = 0;
  for (int i = 0; i < count; ++i) {
    piece_weight[pieces.find(i)] += weight(i);
    total += weight(i);
  }
  const auto small = [&](int i) {
    return static_cast<double>(piece_weight[pieces.find(i)]) <=
           kMaxClusterShare * static_cast<double>(total);
  };
  std::size_t small_points = 0;
  for (int i = 0; i < count; ++i) small_points += small(i);
  if (small_points == 0 || small_points == points.size()) return split;

  // A small piece whose points each have their 16 nearest among themselves can still lie within
  // reach of the object: the object's nearest point to each of its points decides. Within a
  // few noise deviations of it, a piece is the tail of the noise (noise well above the spacing
  // breaks its tails into pieces; the noise is measured only when there are small pieces). And a
  // piece no farther from the object than its own size is a part of the surface seen across a
  // gap (a single range scan's patch behind an occlusion edge), not a cluster apart from it.
  const double noise_reach = kNoiseReach * (noise >= 0.0 ? noise : estimate_noise(points).sigma);
  // The object's nearest point to a point: the first of the object in its row (the row holds
  // every point nearer than that), else from a tree over the object, built when first needed.
  std::optional<KdTree> object;
  std::vector<int> object_index;
  const auto nearest_of_object = [&](int i) {
    for (int c = 1; c < rows.width; ++c)
      if (!small(rows.row(i)[c])) return rows.row(i)[c];
    if (!object) {
      std::vector<Vec3> object_points;
      for (int j = 0; j < count; ++j)
        if (!small(j)) {
          object_points.push_back(points[j]);
          object_index.push_back(j);
        }
      object.emplace(object_points);
    }
    return object_index[object->nearest(points[i])];
  };
  std::vector<char> stray(count, 0);
  std::vector<double> gap_to_object(count, std::numeric_limits<double>::infinity());
  std::vector<Box> extent(count);
  for (int i = 0; i < count; ++i) stray[pieces.find(i)] = small(i);
  for (int i = 0; i < count; ++i) {
    const int root = pieces.find(i);
    if (!stray[root]) continue;
    const int nearest = nearest_of_object(i);
    const double gap = (points[i] - points[nearest]).norm();
    if (joined(i, nearest) || gap <= noise_reach) stray[root] = 0;
    gap_to_object[root] = std::min(gap_to_object[root], gap);
    extent[root].extend(points[i]);
  }
  for (int root = 0; root < count; ++root)
    if (stray[root] && gap_to_object[root] <= diagonal_of(extent[root])) stray[root] = 0;
  std::vector<int> kept;
  std::size_t removed = 0, clusters = 0;
  for (int i = 0; i < count; ++i) {
    const int root = pieces.find(i);
    if (!stray[root]) {
      kept.push_back(i);
      continue;
    }
    removed += weight(i);
    clusters += root == i;  // the root is the piece's lowest index
  }
  if (static_cast<double>(removed) > kMaxStrayShare * static_cast<double>(total)) return split;
  split.kept = std::move(kept);
  split.clusters = clusters;
  return split;
}

}  // namespace vmas
