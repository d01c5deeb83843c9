#include "prepare/fringe.hpp"

#include <algorithm>
#include <numeric>

#include "core/cloud_graph.hpp"
#include "core/disjoint_sets.hpp"
#include "core/principal_axes.hpp"
#include "pcl_backend/cloud_search.hpp"

namespace vmas {
namespace {

// supported_by_noise: a smoothed point is measured against the points within this many support
// radii: far enough to reach from the fringe past an edge to the surface inside it ...
constexpr double kFringeReach = 3.0;
// ... whose support is this quantile of theirs (the fringe itself is among them) ...
constexpr double kFringeReference = 0.75;
// ... among at most about this many points spread evenly through the cloud ...
constexpr std::size_t kFringeReferencePoints = 4000;
// ... and it is fringe below this fraction of that: past about half a deviation beyond an edge,
// where a sampling smeared by Gaussian noise falls below a third of its density inside. (On the
// benchmark's noisy clouds, 0.2-0.3 gave the same results within their spread; 0.3 the least
// mean ε.)
constexpr double kFringeDensity = 0.3;

// The pieces that the kept points form with the points activated so far (kept ones first).
class KeptPieces {
 public:
  KeptPieces(const std::vector<std::vector<int>>& adjacent, const std::vector<char>& kept)
      : adjacent_(adjacent), active_(kept.size(), 0), sets_(static_cast<int>(kept.size())),
        holds_kept_(kept.begin(), kept.end()) {
    for (std::size_t v = 0; v < kept.size(); ++v)
      if (kept[v]) {
        ++count_;
        activate(static_cast<int>(v));
      }
  }
  void activate(int v) {
    active_[v] = 1;
    for (int w : adjacent_[v]) {
      if (!active_[w]) continue;
      const int a = sets_.find(v), b = sets_.find(w);
      if (a == b) continue;
      const bool both = holds_kept_[a] && holds_kept_[b];
      const char either = holds_kept_[a] || holds_kept_[b];
      sets_.unite(a, b);
      holds_kept_[sets_.find(a)] = either;
      count_ -= both;
    }
  }
  int count() const { return count_; }

 private:
  const std::vector<std::vector<int>>& adjacent_;
  std::vector<char> active_;
  internal::DisjointSets sets_;
  std::vector<char> holds_kept_;  // per set root
  int count_ = 0;
};

// Rejoins what a trim (`kept`, one flag per point of `neighbours`) cut in pieces: a thin part whose
// noise leaves its points little support. Of the groups of dropped points that touch two or more
// pieces of the kept ones, the best supported points come back one by one until the pieces are
// joined as the whole groups would join them; the rest of the trim stands.
void rejoin_pieces(const internal::Neighbourhoods& neighbours, const std::vector<int>& support,
                   std::vector<char>& kept) {
  const int n = static_cast<int>(kept.size());
  // Both directions of the k-nearest relation: a point joins whoever lists it too.
  std::vector<std::vector<int>> adjacent(n);
  for (int v = 0; v < n; ++v)
    for (int i = 0; i < neighbours.width; ++i) {
      const int w = neighbours.row(v)[i];
      if (w == v) continue;
      adjacent[v].push_back(w);
      adjacent[w].push_back(v);
    }
  // Pieces of the kept points and groups of the dropped ones; a group's pieces: -1 none yet,
  // -2 two or more.
  internal::DisjointSets sides(n);
  for (int v = 0; v < n; ++v)
    for (int w : adjacent[v])
      if (kept[v] == kept[w]) sides.unite(v, w);
  std::vector<int> piece_of_group(n, -1);
  for (int v = 0; v < n; ++v)
    if (!kept[v])
      for (int w : adjacent[v]) {
        if (!kept[w]) continue;
        int& piece = piece_of_group[sides.find(v)];
        const int touched = sides.find(w);
        piece = piece == -1 || piece == touched ? touched : -2;
      }
  std::vector<int> candidates;
  for (int v = 0; v < n; ++v)
    if (!kept[v] && piece_of_group[sides.find(v)] == -2) candidates.push_back(v);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](int a, int b) { return support[a] > support[b]; });
  // As far as the whole groups would join the pieces (each of them touches kept points), the
  // best supported of them, one by one.
  std::vector<char> with_groups = kept;
  for (int v : candidates) with_groups[v] = 1;
  const int joinable = internal::joined_pieces(neighbours, &with_groups);
  KeptPieces pieces(adjacent, kept);
  for (int v : candidates) {
    if (pieces.count() <= joinable) break;
    pieces.activate(v);
    kept[v] = 1;
  }
}


}  // namespace

std::vector<int> supported_by_noise(const std::vector<Vec3>& smoothed, const std::vector<Vec3>& raw,
                                    double radius) {
  std::vector<int> all(smoothed.size());
  std::iota(all.begin(), all.end(), 0);
  if (smoothed.empty() || raw.empty() || !(radius > 0.0)) return all;
  const Vec3 centroid = internal::centroid_of(raw);
  const internal::FloatCloudSearch raw_search(raw, centroid, false);
  const internal::FloatCloudSearch smoothed_search(smoothed, centroid, false);
  // The points compared with: an even subset (a quantile of a few dozen counts is as good as of
  // hundreds, and the search over all of them within 3 radii took as long as the smoothing).
  const std::size_t stride = std::max<std::size_t>(1, smoothed.size() / kFringeReferencePoints);
  std::vector<Vec3> reference;
  for (std::size_t i = 0; i < smoothed.size(); i += stride) reference.push_back(smoothed[i]);
  const internal::FloatCloudSearch reference_search(reference, centroid, false);
  const auto count = static_cast<std::ptrdiff_t>(smoothed.size());
  const double reach = kFringeReach * radius;
  std::vector<int> support(smoothed.size(), 0);
#pragma omp parallel
  {
    std::vector<int> found;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      support[i] = raw_search.within(smoothed[i], radius, found, squared);
  }
  std::vector<char> kept(smoothed.size(), 1);
#pragma omp parallel
  {
    std::vector<int> around;
    std::vector<float> squared;
    std::vector<int> counts;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      counts.clear();
      reference_search.within(smoothed[i], reach, around, squared);
      for (int r : around)
        if (r * stride != static_cast<std::size_t>(i)) counts.push_back(support[r * stride]);
      if (counts.empty()) {  // too few nearby for the subset: all of them
        smoothed_search.within(smoothed[i], reach, around, squared);
        for (int j : around)
          if (j != i) counts.push_back(support[j]);
      }
      // Alone that far from the rest of the smoothed surface: a stray.
      if (counts.empty()) {
        kept[i] = 0;
        continue;
      }
      const auto at = static_cast<std::size_t>(kFringeReference * (counts.size() - 1));
      std::nth_element(counts.begin(), counts.begin() + at, counts.end());
      kept[i] = support[i] >= kFringeDensity * counts[at];
    }
  }
  const auto kept_points = [&] {
    std::vector<Vec3> trimmed;
    for (std::size_t i = 0; i < smoothed.size(); ++i)
      if (kept[i]) trimmed.push_back(smoothed[i]);
    return trimmed;
  };
  // A trim that leaves the data in more pieces went through a thin part, not along an edge.
  if (std::find(kept.begin(), kept.end(), 0) != kept.end()) {
    const internal::Neighbourhoods neighbours =
        internal::k_nearest_all(smoothed, internal::kJoiningNeighbours);
    const int pieces = internal::joined_pieces(neighbours);
    // The kept points' own graph; only when the rows of all the points, which bound its pieces
    // from above, leave more.
    const auto cut = [&] {
      return internal::joined_pieces(neighbours, &kept) > pieces &&
             internal::joined_pieces(internal::k_nearest_all(
                 kept_points(), internal::kJoiningNeighbours)) > pieces;
    };
    if (cut()) {
      rejoin_pieces(neighbours, support, kept);
      if (cut()) return all;
    }
  }
  std::vector<int> supported;
  for (std::size_t i = 0; i < smoothed.size(); ++i)
    if (kept[i]) supported.push_back(static_cast<int>(i));
  return supported;
}


}  // namespace vmas
