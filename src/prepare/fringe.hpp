#pragma once
// The fringe that noise spreads past a scan's edges and tips, trimmed after smoothing.
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

// Indices of the `smoothed` points (smooth_mls of `raw`, in the same order) that the noisy data
// support, ascending. Noise spreads a sampling past its surface's edges and tips (a wing's, a
// finger's) by two or three deviations, and smoothing along the normals keeps that fringe, on
// which spheres then sit outside the shape. A fringe point has few raw points within `radius`
// (the smoothing's scale, at least two spacings) against the smoothed points around it (within
// 3 radii): under 0.3 of their upper quartile, it goes; so does a point with no other within 3
// radii. A uniformly sparse part of a scan (far from the scanner) keeps its points: the points
// around are as sparse. When the points kept would fall into more pieces than all of them (as
// the shape's graph joins them: cloud_graph.hpp), the trim cut through a thin part: the dropped
// points there that best rejoin the pieces come back, and if the pieces still are more, every
// point is returned.
std::vector<int> supported_by_noise(const std::vector<Vec3>& smoothed, const std::vector<Vec3>& raw,
                                    double radius);

}  // namespace vmas
