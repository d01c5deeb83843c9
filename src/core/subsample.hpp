#pragma once
// Coarse-to-fine for big clouds: the optimisation needs a few hundred points per sphere, not
// millions. A cloud above a point budget is thinned to one point per cell of a voxel grid sized
// so that about the budget remains; every other point is represented by its cell's point (its
// label, in the end). The grid evens out the density of merged scans as a side effect.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

struct Subsample {
  std::vector<int> kept;            // ascending indices of the points kept, one per occupied cell
  std::vector<int> representative;  // for every point: the index into `kept` of its cell's point
  double leaf = 0.0;                // edge length of the cells (0: every point kept)
};

// Keeps every point when there are at most `budget` (or budget is 0). Otherwise the cell's point
// is the one nearest the cell's centre (ties: the lower index), and between 0.8 and 1 times the
// budget remain on a surface (a few grid sizes are tried). Points of different `groups` (one
// small number per point, or none) never share a cell's point. Deterministic.
Subsample subsample(const std::vector<Vec3>& points, std::size_t budget,
                    const std::vector<std::uint8_t>& groups = {});

}  // namespace vmas
