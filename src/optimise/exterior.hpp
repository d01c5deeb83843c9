#pragma once
// The outside of a sampled surface, as voxels: a grid over the points whose cells near a point
// are walls, flood-filled from its border through the other cells. A closed sampling walls the
// inside off, and the centre of a medial ball is never in the fill: inside a thick part it is in
// a free cell the fill did not reach, inside a thin part in a wall. Through a gap in the walls
// (a hole, an open side, samples sparser than the cells) the fill reaches the inside too.
#include <cstdint>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class ExteriorGrid {
 public:
  // Cells of `cell` (at most 256 along the longest side); every sample walls its cell and the
  // 26 around it, so that gaps up to two cells wide stay closed.
  ExteriorGrid(const std::vector<Vec3>& points, double cell);

  // Whether the fill reached `p` (positions off the grid are outside).
  bool outside(const Vec3& p) const;

 private:
  // One bit per cell.
  class CellBits {
   public:
    CellBits() = default;
    explicit CellBits(std::size_t cells) : words_((cells + 63) / 64, 0) {}
    bool empty() const { return words_.empty(); }
    bool operator[](std::size_t i) const { return (words_[i >> 6] >> (i & 63)) & 1u; }
    void set(std::size_t i) { words_[i >> 6] |= std::uint64_t{1} << (i & 63); }

   private:
    std::vector<std::uint64_t> words_;
  };

  Vec3 low_;
  double cell_ = 0.0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  CellBits outside_;  // by cell: reached by the fill
};

}  // namespace internal
}  // namespace vmas
