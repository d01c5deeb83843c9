#include "optimise/split.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "vmas/error.hpp"

namespace vmas {

void SplitOptions::validate() const {
  if (!(max_fraction > 0.0 && max_fraction <= 1.0))
    throw InvalidOption("max_fraction",
                        "must be in (0, 1] (got " + std::to_string(max_fraction) + ")");
  if (large_count_share < 1) throw InvalidOption("large_count_share", "must be at least 1");
  if (max_per_round < 1)
    throw InvalidOption("max_per_round",
                        "must be at least 1 (got " + std::to_string(max_per_round) + ")");
}

std::vector<int> select_clusters_to_split(const std::vector<double>& cluster_errors,
                                          const std::vector<std::vector<int>>& adjacency,
                                          const std::vector<bool>& eligible, int max_count) {
  const int count = static_cast<int>(cluster_errors.size());
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return cluster_errors[a] > cluster_errors[b]; });
  std::vector<bool> blocked(count, false);
  std::vector<int> chosen;
  for (int c : order) {
    if (static_cast<int>(chosen.size()) >= max_count) break;
    if (!eligible[c] || blocked[c]) continue;
    chosen.push_back(c);
    for (int neighbour : adjacency[c]) blocked[neighbour] = true;
  }
  return chosen;
}

}  // namespace vmas
