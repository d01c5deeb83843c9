#pragma once
// Which way a cloud's normals face, read from outside: a point that a viewer far away sees has
// its outward normal turned toward that viewer. Each point is judged on its own, so a mistake
// stays where it is made, where propagation from neighbour to neighbour carries it over a whole
// region (docs/noise.md, step 4).
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

// For each point, the mean of −n·d over the view directions d (spread over the sphere) from which
// it is seen, in [−1, 1]: positive when its normal faces the viewers, 0 when no view sees it
// (deep in a cavity). A view is an orthographic depth buffer of square pixels of side `pixel`;
// a point is seen when it lies within `pixel` of its pixel's front (the noise left after
// smoothing spreads the front over a band). A pixel is at least the bounding box's diagonal over
// 2√n, so that a view holds about 4 pixels per point at most. Deterministic whatever the thread
// count.
std::vector<double> visibility_votes(const std::vector<Vec3>& points,
                                     const std::vector<Vec3>& normals, double pixel);

}  // namespace vmas
