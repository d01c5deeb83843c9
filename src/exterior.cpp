#include "exterior.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace vmas::internal {

namespace {
// The cells of the levels, in sample spacings.
constexpr std::array<double, 2> kCellInSpacings = {1.0, 0.75};
// The most cells along the longest side: 16 M cells and bytes at most per level.
constexpr int kMaxCellsPerSide = 256;
// Free cells of margin around the points' box, so that the fill goes round the whole surface.
constexpr int kMargin = 3;

enum : std::uint8_t { kFree = 0, kWall = 1, kOutside = 2 };
}  // namespace

ExteriorGrid::Level::Level(const std::vector<Vec3>& points, double cell_size) {
  Box box;
  for (const Vec3& p : points) box.extend(p);
  cell = std::max(cell_size, box.sizes().maxCoeff() / kMaxCellsPerSide);
  low = box.min() - Vec3::Constant(kMargin * cell);
  const auto cells_along = [&](double side) {
    return static_cast<int>(std::ceil(side / cell)) + 2 * kMargin + 1;
  };
  nx = cells_along(box.sizes().x());
  ny = cells_along(box.sizes().y());
  nz = cells_along(box.sizes().z());
  const std::size_t layer = static_cast<std::size_t>(nx) * ny;
  state.assign(layer * nz, kFree);
  // Every sample walls its cell and the 26 around it: gaps up to two cells wide stay closed.
  for (const Vec3& p : points) {
    const Vec3 c = (p - low) / cell;
    const int x = static_cast<int>(c.x()), y = static_cast<int>(c.y()), z = static_cast<int>(c.z());
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          state[(z + dz) * layer + static_cast<std::size_t>(y + dy) * nx + (x + dx)] = kWall;
  }
  // Breadth-first over face neighbours from a corner (the margin is free all round).
  std::vector<std::size_t> queue{0};
  state[0] = kOutside;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t i = queue[head];
    const int x = static_cast<int>(i % nx), y = static_cast<int>((i / nx) % ny),
              z = static_cast<int>(i / layer);
    const std::array<std::pair<bool, std::ptrdiff_t>, 6> steps = {
        {{x + 1 < nx, 1},
         {x > 0, -1},
         {y + 1 < ny, nx},
         {y > 0, -nx},
         {z + 1 < nz, static_cast<std::ptrdiff_t>(layer)},
         {z > 0, -static_cast<std::ptrdiff_t>(layer)}}};
    for (const auto& [on_grid, offset] : steps) {
      if (!on_grid) continue;
      const std::size_t j = i + offset;
      if (state[j] != kFree) continue;
      state[j] = kOutside;
      queue.push_back(j);
    }
  }
}

bool ExteriorGrid::Level::outside(const Vec3& p) const {
  const Vec3 c = (p - low) / cell;
  if (!(c.minCoeff() >= 0.0)) return true;  // also NaN
  const auto x = static_cast<std::size_t>(c.x()), y = static_cast<std::size_t>(c.y()),
             z = static_cast<std::size_t>(c.z());
  if (x >= std::size_t(nx) || y >= std::size_t(ny) || z >= std::size_t(nz)) return true;
  return state[(z * ny + y) * nx + x] == kOutside;
}

ExteriorGrid::ExteriorGrid(const std::vector<Vec3>& points, double spacing) {
  if (points.empty() || !(spacing > 0.0)) return;
  for (double cells : kCellInSpacings) levels_.emplace_back(points, cells * spacing);
}

bool ExteriorGrid::outside(const Vec3& p) const {
  return std::any_of(levels_.begin(), levels_.end(),
                     [&](const Level& level) { return level.outside(p); });
}

}  // namespace vmas::internal
