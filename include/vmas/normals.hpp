#pragma once
// Normal estimation for point clouds that come without normals, and consistent outward
// orientation (minimum spanning tree propagation over the k-NN graph, Hoppe et al. 1992, then a
// global check that the normals point away from the inside).
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

struct NormalOptions {
  int k = 16;  // neighbours used for the PCA plane fit and for the orientation graph
  void validate() const;  // throws InvalidOption
};

// Unit normals, one per point, oriented consistently and outward.
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options);

// Flips given normals so that neighbours agree and the whole set points outward.
void orient_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k);

}  // namespace vmas
