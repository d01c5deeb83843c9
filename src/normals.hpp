#pragma once
// Normal estimation for point clouds that come without normals, and consistent outward
// orientation (minimum spanning tree propagation over the k-NN graph, Hoppe et al. 1992, then a
// global check that the normals point away from the inside).
#include <vector>

#include "vmas/prepare.hpp"

namespace vmas {

// Unit normals, one per point, from a plane fit to each point and its k nearest neighbours, then
// oriented as by orient_normals. Throws InvalidOption for a bad k and InvalidInput for fewer than
// k + 1 points. Deterministic whatever the thread count; never returns NaN (a degenerate
// neighbourhood gets a finite normal whose line may be arbitrary).
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options);

// Flips given normals so that neighbours agree and each connected component of the k-NN graph
// points outward. Also normalises them and replaces NaN or zero ones by finite ones. Throws
// InvalidOption for a bad k and InvalidInput when the two sizes differ.
void orient_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k);

// How much unit normals point away from the points' centroid: Σ (p − c)·n / Σ |p − c| over the
// points listed in `subset` (all when empty), in [−1, 1]. Near 1 for a roundish closed surface
// with outward normals, near −1 with inward ones, near 0 for flat data or normals of random sign.
double outward_flux(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                    const std::vector<int>& subset = {});

}  // namespace vmas
