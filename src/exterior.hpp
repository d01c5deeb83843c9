#pragma once
// The outside of a sampled surface, as voxels: a grid over the points whose cells near a point
// are walls, flood-filled from its border through the other cells. A closed sampling walls the
// inside off, and the centre of a medial ball is never in the fill: inside a thick part it is in
// a free cell the fill did not reach, inside a thin part in a wall.
#include <cstdint>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class ExteriorGrid {
 public:
  // `spacing`: the typical distance between neighbouring samples (about the distance to the
  // sixth nearest).
  ExteriorGrid(const std::vector<Vec3>& points, double spacing);

  // Whether the fill reached `p` (positions off the grid are outside).
  bool outside(const Vec3& p) const;

 private:
  // One grid and its fill. The coarse level's walls have no gap where samples are a spacing
  // apart, but they also close narrow gaps between parts (an ear against a head) into pockets
  // that the fill misses; the fine level's thinner walls leave those open. Through its gaps the
  // fine fill may reach the inside of sparse data: its probe check (MedialProjector) then drops
  // the grid.
  struct Level {
    Level(const std::vector<Vec3>& points, double cell);
    bool outside(const Vec3& p) const;

    Vec3 low;
    double cell = 0.0;
    int nx = 0, ny = 0, nz = 0;
    std::vector<std::uint8_t> state;  // by cell: free, wall, or reached by the fill
  };
  std::vector<Level> levels_;
};

}  // namespace internal
}  // namespace vmas
