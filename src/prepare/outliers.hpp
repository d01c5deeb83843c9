#pragma once
// Strays among a scan's points: PCL's statistical outlier rule, with the sparse parts of a clean
// sampling (which the rule takes for strays) given back.
#include <vector>

#include "prepare/prepare.hpp"

namespace vmas {

// Indices of the points kept by the rule of PCL's StatisticalOutlierRemoval (mean distance to
// the outlier_k nearest neighbours within outlier_deviations standard deviations of the cloud's
// mean; the filter keeps its searcher private, so the rule is computed here), ascending; repeated (at most 4 passes) while a pass removes between 0.5 % and 2 % of
// the points. A first pass removing more than 2 % has found uneven density: every point stays.
// Clouds too small for it keep every point.
std::vector<int> inlier_indices(const std::vector<Vec3>& points, const DenoiseOptions& options);

// `inliers` (from inlier_indices) and the points it left out that continue the sampling of their
// nearest kept neighbour, near it or on its plane, ascending: for a clean sampling, whose sparse
// parts (a random sampling's sparse tail, the rim of a regular grid, a thin wall) the
// statistical rule takes for strays. When most of the points left out do not continue it, they
// are a scatter of strays, and only those on their neighbour's surface join `inliers`.
std::vector<int> with_sparse_parts(const std::vector<Vec3>& points, const std::vector<int>& inliers,
                                   const DenoiseOptions& options);

}  // namespace vmas
