#pragma once
// Sphere splitting (paper §3.4): which clusters get a new sphere this round.
#include <vector>

namespace vmas {

struct SplitOptions {
  double max_fraction = 0.2;  // at most this fraction of the current sphere count per round
  int max_per_round = 10;     // and at most this many (sphere-count targets only) ...
  int large_count_share = 20;  // ... or 1/this of the current count when that is more
  void validate() const;      // throws InvalidOption
};

// Clusters to split, worst error first: only `eligible` ones (an error target is the caller's to
// apply), none adjacent to a cluster already chosen in this round, at most `max_count`.
std::vector<int> select_clusters_to_split(const std::vector<double>& cluster_errors,
                                          const std::vector<std::vector<int>>& adjacency,
                                          const std::vector<bool>& eligible, int max_count);

}  // namespace vmas
