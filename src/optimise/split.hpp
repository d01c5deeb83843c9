#pragma once
// Sphere splitting (paper §3.4): which clusters get a new sphere this round.
#include <vector>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// Clusters to split, worst error first: only `eligible` ones (an error target is the caller's to
// apply), none adjacent to a cluster already chosen in this round, at most `max_count`.
std::vector<int> select_clusters_to_split(const std::vector<double>& cluster_errors,
                                          const std::vector<std::vector<int>>& adjacency,
                                          const std::vector<bool>& eligible, int max_count);

}  // namespace vmas
