#pragma once
// Sphere splitting (paper §3.4): which clusters get a new sphere this round.
#include <vector>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// Clusters to split, worst error first: only `eligible` ones (an error target is the caller's to
// apply), none adjacent to a cluster already chosen in this round, at most `max_count`. The
// round ends at a cluster whose error is below `blocked_share` times that of one passed over for
// being adjacent (0: never): its split would take the place that one's takes next round.
std::vector<int> select_clusters_to_split(const std::vector<double>& cluster_errors,
                                          const std::vector<std::vector<int>>& adjacency,
                                          const std::vector<bool>& eligible, int max_count,
                                          double blocked_share = 0.0);

}  // namespace vmas
