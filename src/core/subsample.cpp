#include "core/subsample.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "core/radix_sort.hpp"
#include "vmas/error.hpp"

namespace vmas {

namespace {

// Cells per axis stay below 2^20, so that three cell coordinates and a group (3 bits) pack into
// one 64-bit key.
constexpr int kBitsPerAxis = 20;
constexpr int kGroupBits = 3;
constexpr double kMaxCells = double(1 << kBitsPerAxis) - 1.0;
// Grid sizes tried; the count usually lands in range at the second or third.
constexpr int kMaxTries = 8;
constexpr double kLowestFill = 0.8;

struct Grid {
  Vec3 origin;
  double leaf;

  Eigen::Array3d cell_of(const Vec3& p) const {
    return ((p - origin) / leaf).array().floor().min(kMaxCells).max(0.0);
  }
  std::uint64_t key(const Vec3& p, std::uint8_t group) const {
    const Eigen::Array3d c = cell_of(p);
    return (static_cast<std::uint64_t>(c.x()) << (2 * kBitsPerAxis + kGroupBits)) |
           (static_cast<std::uint64_t>(c.y()) << (kBitsPerAxis + kGroupBits)) |
           (static_cast<std::uint64_t>(c.z()) << kGroupBits) | group;
  }
  double squared_distance_to_centre(const Vec3& p) const {
    const Vec3 centre = origin + leaf * (cell_of(p) + 0.5).matrix();
    return (p - centre).squaredNorm();
  }
};

std::uint8_t group_of(const std::vector<std::uint8_t>& groups, std::size_t i) {
  return groups.empty() ? 0 : groups[i];
}

std::size_t occupied_cells(const std::vector<Vec3>& points, const std::vector<std::uint8_t>& groups,
                           const Grid& grid, std::vector<std::uint64_t>& keys) {
  keys.resize(points.size());
  const auto n = static_cast<std::ptrdiff_t>(points.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) keys[i] = grid.key(points[i], group_of(groups, i));
  internal::radix_sort(keys);
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace

Subsample subsample(const std::vector<Vec3>& points, std::size_t budget,
                    const std::vector<std::uint8_t>& groups) {
  if (!groups.empty() && groups.size() != points.size())
    throw InvalidArgument("subsample: one group per point");
  for (std::uint8_t g : groups)
    if (g >= (1 << kGroupBits)) throw InvalidArgument("subsample: groups must be below 8");
  Subsample result;
  const std::size_t n = points.size();
  if (budget == 0 || n <= budget) {
    result.kept.resize(n);
    std::iota(result.kept.begin(), result.kept.end(), 0);
    result.representative = result.kept;
    return result;
  }
  const Box box = bounding_box(points);
  const Vec3 sizes = box.sizes();
  // First guess: a closed surface has about half the area of its bounding box.
  const double box_area =
      2.0 * (sizes.x() * sizes.y() + sizes.y() * sizes.z() + sizes.z() * sizes.x());
  const double finest = sizes.maxCoeff() / kMaxCells;
  Grid grid{box.min(), std::max(std::sqrt(0.5 * box_area / budget), finest)};
  if (!(grid.leaf > 0.0)) grid.leaf = 1.0;  // a flat or degenerate box: any size will do
  std::vector<std::uint64_t> keys;
  // Cells ∝ leaf^-d: d = 2 on a surface, 1 along a line, 0 where cells are finer than the
  // points; d is re-measured from the last two tries.
  double exponent = 2.0, previous_leaf = 0.0;
  std::size_t previous_count = 0;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    const std::size_t count = occupied_cells(points, groups, grid, keys);
    const double fill = double(count) / budget;
    if (fill <= 1.0 && fill >= kLowestFill) break;
    if (attempt > 0) {
      if (count == previous_count && fill < kLowestFill) break;  // coincident points: no finer
      exponent = count == previous_count ? 0.5  // cells finer than the points: take a big step
                                         : std::clamp(std::log(double(previous_count) / count) /
                                                          std::log(grid.leaf / previous_leaf),
                                                      0.5, 3.0);
    }
    previous_leaf = grid.leaf;
    previous_count = count;
    grid.leaf = std::max(grid.leaf * std::pow(fill / 0.9, 1.0 / exponent), finest);  // aim at 90 %
  }

  std::vector<std::uint64_t>().swap(keys);
  // The point of each cell: the one nearest the cell's centre, the lowest index among equals
  // (points are visited in index order, and only a nearer one replaces the cell's). A table of
  // the cells, not a sort of the points: a 10 M-point cloud held 320 MB of sort keys here.
  struct Cell {
    int point;
    double distance;
    int position = -1;  // of `point` in result.kept
  };
  std::unordered_map<std::uint64_t, Cell> cells;
  cells.reserve(budget);
  for (std::size_t i = 0; i < n; ++i) {
    const double distance = grid.squared_distance_to_centre(points[i]);
    const auto [cell, added] =
        cells.try_emplace(grid.key(points[i], group_of(groups, i)), Cell{int(i), distance});
    if (!added && distance < cell->second.distance) cell->second = {int(i), distance};
  }
  result.kept.reserve(cells.size());
  for (const auto& [key, cell] : cells) result.kept.push_back(cell.point);
  std::sort(result.kept.begin(), result.kept.end());
  for (auto& [key, cell] : cells)
    cell.position = static_cast<int>(
        std::lower_bound(result.kept.begin(), result.kept.end(), cell.point) - result.kept.begin());
  result.representative.resize(n);
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < count; ++i)
    result.representative[i] = cells.at(grid.key(points[i], group_of(groups, i))).position;
  result.leaf = grid.leaf;
  return result;
}

}  // namespace vmas
