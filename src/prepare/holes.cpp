#include "prepare/holes.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "core/disjoint_sets.hpp"
#include "core/kdtree.hpp"
#include "core/quadric_fit.hpp"

namespace vmas {

namespace {

constexpr int kNeighbours = 16;
// A smoothed cloud's density is uneven at the scale of its smoothing (MLS fits on a grid): 16
// directions leave a gap past kRimGapRadians at 1-1.5 % of its points, and chains of them read
// as holes (docs/noise.md, step 7).
constexpr int kSmoothedNeighbours = 24;
// A half-disc of neighbours leaves a gap of ~180°; 16 random directions leave more than 150°
// with probability ~0.5 %.
constexpr double kRimGapRadians = 150.0 * M_PI / 180.0;
constexpr int kMinRimPoints = 10;
// A half-disc of neighbours spreads 0.28 as much across the rim as along it: a rim's
// neighbourhood is neither a line (a thin part sampled by one row of points) nor thick off its
// quadric, its summed squared residual above kMaxThicknessRatio × its squared spread across (a
// thin part sampled around, whose normals say little). Off its plane the curved side of a thin
// tube is thick too: 193 of the 256 points at the cut of the vessel's cap, which crosses parts
// 2-3 % of the diagonal wide. 0.2 and 0.05 found fewer holes on open clouds or more on closed
// ones than 0.1 (docs/noise.md, step 7).
constexpr double kMinWidthRatio = 0.05, kMaxThicknessRatio = 0.1;
// Narrower holes are gaps of the sampling, in neighbourhood reaches (median).
constexpr double kMinHoleWidth = 3.0;
// Rim points link to their kRimLinks nearest rim points within kRimLinkReach of their
// neighbourhood's reach.
constexpr int kRimLinks = 4;
constexpr double kRimLinkReach = 1.5;
// A lid's outline: the rim's farthest point in each sector around its centre.
constexpr int kLidSectors = 64;
// The lids of a cloud's holes hold at most this many points in all (a KdTree of them: ~3 MB).
constexpr int kLidPoints = 40000;

// Whether `p` (normal `n`) sees its neighbours `around` on one side only.
bool on_rim(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, int p,
            const std::vector<int>& around, std::vector<double>& angles) {
  const Vec3& n = normals[p];
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  angles.clear();
  for (int q : around) {
    if (q == p) continue;
    if (normals[q].dot(n) < 0.0) return false;  // a fold: two sheets meet here
    const Vec3 d = points[q] - points[p];
    angles.push_back(std::atan2(d.dot(v), d.dot(u)));
  }
  if (angles.size() < 2) return false;
  std::sort(angles.begin(), angles.end());
  double widest = angles.front() + 2.0 * M_PI - angles.back();
  for (std::size_t i = 1; i < angles.size(); ++i) widest = std::max(widest, angles[i] - angles[i - 1]);
  if (!(widest > kRimGapRadians)) return false;
  // Only the few points that see a gap pay for the fit.
  const internal::QuadricFit surface = internal::fit_quadric(points, around);
  return surface.valid && surface.spread[1] >= kMinWidthRatio * surface.spread[2] &&
         surface.residual_squares <= kMaxThicknessRatio * surface.spread[1];
}

}  // namespace

std::vector<Hole> find_holes(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                             bool smoothed) {
  const int neighbours = smoothed ? kSmoothedNeighbours : kNeighbours;
  const int count = static_cast<int>(points.size());
  if (count <= neighbours || normals.size() != points.size()) return {};
  const KdTree tree(points);
  std::vector<double> reach(count, 0.0);  // distance to the farthest of the neighbours
  std::vector<char> rim(count, 0);
#pragma omp parallel
  {
    std::vector<int> around;
    std::vector<double> squared, angles;
#pragma omp for schedule(static)
    for (int p = 0; p < count; ++p) {
      tree.k_nearest(points[p], neighbours + 1, around, squared);
      reach[p] = std::sqrt(squared.back());
      rim[p] = on_rim(points, normals, p, around, angles);
    }
  }
  std::vector<int> rim_points;
  std::vector<Vec3> rim_positions;
  for (int p = 0; p < count; ++p)
    if (rim[p]) {
      rim_points.push_back(p);
      rim_positions.push_back(points[p]);
    }
  if (rim_points.empty()) return {};
  // Not every point along a rim sees the gap: rim points link across a few others.
  const int rim_count = static_cast<int>(rim_points.size());
  const KdTree rim_tree(rim_positions);
  internal::DisjointSets rims(rim_count);
  std::vector<int> nearest;
  std::vector<double> squared;
  for (int i = 0; i < rim_count; ++i) {
    rim_tree.k_nearest(rim_positions[i], kRimLinks + 1, nearest, squared);
    for (std::size_t j = 1; j < nearest.size(); ++j)
      if (std::sqrt(squared[j]) <= kRimLinkReach * reach[rim_points[i]]) rims.unite(i, nearest[j]);
  }
  std::unordered_map<int, std::pair<std::vector<int>, Box>> by_root;
  for (int i = 0; i < rim_count; ++i) {
    auto& [members, box] = by_root[rims.find(i)];
    members.push_back(rim_points[i]);
    box.extend(points[rim_points[i]]);
  }
  const double min_width = kMinHoleWidth * median(reach);
  std::vector<Hole> holes;
  for (auto& [root, rim_of] : by_root) {
    const double width = rim_of.second.diagonal().norm();
    if (static_cast<int>(rim_of.first.size()) >= kMinRimPoints && width >= min_width)
      holes.push_back({width, std::move(rim_of.first)});
  }
  std::sort(holes.begin(), holes.end(), [](const Hole& a, const Hole& b) {
    return a.width != b.width ? a.width > b.width : a.rim < b.rim;
  });
  return holes;
}

std::vector<Vec3> rim_points(const Hole& hole, const std::vector<Vec3>& points) {
  std::vector<Vec3> rim;
  rim.reserve(hole.rim.size());
  for (int p : hole.rim) rim.push_back(points[p]);
  return rim;
}

RimPlane rim_plane(const std::vector<Vec3>& rim, const std::vector<Vec3>& cloud) {
  RimPlane plane;
  if (rim.empty()) return plane;
  for (const Vec3& p : rim) plane.centre += p;
  plane.centre /= static_cast<double>(rim.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : rim) scatter += (p - plane.centre) * (p - plane.centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(scatter);
  const Vec3 normal = axes.eigenvectors().col(0);  // the smallest spread: across the rim
  std::ptrdiff_t ahead = 0;
  for (const Vec3& p : cloud) ahead += (p - plane.centre).dot(normal) > 0.0 ? 1 : -1;
  plane.outward = ahead > 0 ? Vec3(-normal) : normal;
  for (const Vec3& p : rim) {
    const Vec3 offset = p - plane.centre;
    plane.radius = std::max(plane.radius, (offset - offset.dot(normal) * normal).norm());
  }
  return plane;
}

std::vector<Vec3> lid_points(const std::vector<Vec3>& rim, const RimPlane& plane, double spacing,
                             int at_most) {
  if (rim.size() < 2 || !(plane.radius > 0.0) || at_most < 1) return {};
  if (!(spacing > 0.0)) spacing = median_spacing(KdTree(rim), rim);
  const Vec3 u = plane.outward.unitOrthogonal(), v = plane.outward.cross(u);
  const auto sector_of = [&](double x, double y) {
    const double turn = (std::atan2(y, x) + M_PI) / (2.0 * M_PI);
    return std::min(kLidSectors - 1, static_cast<int>(turn * kLidSectors));
  };
  std::vector<double> reach(kLidSectors, -1.0), height(kLidSectors, 0.0);
  for (const Vec3& p : rim) {
    const Vec3 offset = p - plane.centre;
    const int sector = sector_of(offset.dot(u), offset.dot(v));
    const double r = std::hypot(offset.dot(u), offset.dot(v));
    if (r <= reach[sector]) continue;
    reach[sector] = r;
    height[sector] = offset.dot(plane.outward);
  }
  // A sector without rim points takes the nearer reach of the nearest sectors that have some.
  std::vector<double> filled = reach, lifted = height;
  for (int s = 0; s < kLidSectors; ++s) {
    if (reach[s] >= 0.0) continue;
    for (int step = 1; step < kLidSectors && filled[s] < 0.0; ++step) {
      const int before = (s - step + kLidSectors) % kLidSectors, after = (s + step) % kLidSectors;
      if (reach[before] < 0.0 && reach[after] < 0.0) continue;
      const int nearer = reach[after] < 0.0 || (reach[before] >= 0.0 && reach[before] < reach[after])
                             ? before : after;
      filled[s] = reach[nearer];
      lifted[s] = height[nearer];
    }
  }
  const double step = std::max(spacing, plane.radius * std::sqrt(M_PI / at_most));
  const int steps = static_cast<int>(std::ceil(plane.radius / step));
  std::vector<Vec3> lid;
  for (int i = -steps; i <= steps; ++i)
    for (int j = -steps; j <= steps; ++j) {
      const double x = i * step, y = j * step;
      const int sector = sector_of(x, y);
      const double r = std::hypot(x, y);
      if (r <= filled[sector])
        lid.push_back(plane.centre + x * u + y * v +
                      (r > 0.0 ? r / filled[sector] : 0.0) * lifted[sector] * plane.outward);
    }
  return lid;
}

std::vector<Vec3> lid_points(const std::vector<Hole>& holes, const std::vector<Vec3>& points,
                             double spacing) {
  std::vector<Vec3> lids;
  const int per_hole = std::max(1, kLidPoints / std::max(1, static_cast<int>(holes.size())));
  for (const Hole& hole : holes) {
    const std::vector<Vec3> rim = rim_points(hole, points);
    const std::vector<Vec3> lid = lid_points(rim, rim_plane(rim, points), spacing, per_hole);
    lids.insert(lids.end(), lid.begin(), lid.end());
  }
  return lids;
}

}  // namespace vmas
