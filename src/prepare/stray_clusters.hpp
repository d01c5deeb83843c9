#pragma once
// Stray clusters: small groups of points apart from the object (a registration's leftovers, a
// passer-by, dust in front of the scanner). A group of a few dozen points stops no statistical
// outlier rule (each of its points has close neighbours: one another), yet one sphere reaches
// out to it and the skeleton lies ten times farther from the object than it should.
#include <cstddef>
#include <vector>

#include "core/cloud_graph.hpp"
#include "vmas/types.hpp"

namespace vmas {

struct StrayClusterSplit {
  std::vector<int> kept;     // indices of the points kept, ascending
  std::size_t clusters = 0;  // groups removed
};

// Splits `points` into the pieces a sampling holds together: two points are joined when one is
// among the other's 16 nearest, or is the object's nearest point to it, and they lie within twice
// the cloud's median distance to the 16th nearest neighbour, or within twice the spacing of the
// sampling around either of them (the largest nearest-neighbour distance among its 16 nearest):
// a sparse part of the sampling (a thin antenna, a tail, an under-scanned base) stays joined by
// its own density, while a stray, whose neighbours are the object's points, cannot reach out by
// its own emptiness. Pieces holding at most 1 % of the weight (`weights`: how many input points
// each point stands for; empty: one each) are removed when they lie farther from the object
// (the pieces holding more) than 5 noise deviations (`noise`, absolute; negative: measured by
// estimate_noise when there are small pieces: the noise's tails) and than
// their own size (a patch seen across an occlusion gap is a part of the object), unless such
// pieces together hold more than 10 %: data made of many small pieces is a sparse sampling, not
// an object with strays. Deterministic.
StrayClusterSplit without_stray_clusters(const std::vector<Vec3>& points,
                                         const std::vector<std::size_t>& weights = {},
                                         double noise = -1.0);
// As above, with `rows` = k_nearest_all(points, kJoiningNeighbours) already found (preparation
// hands them on to the normals).
StrayClusterSplit without_stray_clusters(const std::vector<Vec3>& points,
                                         const internal::Neighbourhoods& rows,
                                         const std::vector<std::size_t>& weights, double noise);

}  // namespace vmas
