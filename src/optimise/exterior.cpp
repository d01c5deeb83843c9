#include "optimise/exterior.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace vmas::internal {

namespace {
// The most cells along the longest side: 16 M cells, 2 MB of bits, at most.
constexpr int kMaxCellsPerSide = 256;
// Free cells of margin around the points' box, so that the fill goes round the whole surface.
constexpr int kMargin = 3;
}  // namespace

ExteriorGrid::ExteriorGrid(const std::vector<Vec3>& points, double cell) {
  if (points.empty() || !(cell > 0.0)) return;
  Box box;
  for (const Vec3& p : points) box.extend(p);
  cell_ = std::max(cell, box.sizes().maxCoeff() / kMaxCellsPerSide);
  low_ = box.min() - Vec3::Constant(kMargin * cell_);
  const auto cells_along = [&](double side) {
    return static_cast<int>(std::ceil(side / cell_)) + 2 * kMargin + 1;
  };
  nx_ = cells_along(box.sizes().x());
  ny_ = cells_along(box.sizes().y());
  nz_ = cells_along(box.sizes().z());
  const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
  CellBits wall(layer * nz_);
  outside_ = CellBits(layer * nz_);
  for (const Vec3& p : points) {
    const Vec3 c = (p - low_) / cell_;
    const int x = static_cast<int>(c.x()), y = static_cast<int>(c.y()), z = static_cast<int>(c.z());
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          wall.set((z + dz) * layer + static_cast<std::size_t>(y + dy) * nx_ + (x + dx));
  }
  // Breadth-first over face neighbours from a corner (the margin is free all round), one front
  // at a time: a front is a surface through the grid, far fewer cells than the fill reaches.
  std::vector<std::uint32_t> front{0}, next;
  outside_.set(0);
  while (!front.empty()) {
    next.clear();
    for (const std::size_t i : front) {
      const int x = static_cast<int>(i % nx_), y = static_cast<int>((i / nx_) % ny_),
                z = static_cast<int>(i / layer);
      const std::array<std::pair<bool, std::ptrdiff_t>, 6> steps = {
          {{x + 1 < nx_, 1},
           {x > 0, -1},
           {y + 1 < ny_, nx_},
           {y > 0, -nx_},
           {z + 1 < nz_, static_cast<std::ptrdiff_t>(layer)},
           {z > 0, -static_cast<std::ptrdiff_t>(layer)}}};
      for (const auto& [on_grid, offset] : steps) {
        if (!on_grid) continue;
        const std::size_t j = i + offset;
        if (wall[j] || outside_[j]) continue;
        outside_.set(j);
        next.push_back(static_cast<std::uint32_t>(j));
      }
    }
    front.swap(next);
  }
}

bool ExteriorGrid::outside(const Vec3& p) const {
  if (outside_.empty()) return false;
  const Vec3 c = (p - low_) / cell_;
  if (!(c.minCoeff() >= 0.0)) return true;  // also NaN
  const auto x = static_cast<std::size_t>(c.x()), y = static_cast<std::size_t>(c.y()),
             z = static_cast<std::size_t>(c.z());
  if (x >= std::size_t(nx_) || y >= std::size_t(ny_) || z >= std::size_t(nz_)) return true;
  return outside_[(z * ny_ + y) * nx_ + x];
}

}  // namespace vmas::internal
