// The cleaning stage: what every input goes through before anything else.
#include "vmas/io.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/density_mean.hpp"
#include "core/radix_sort.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace {

// `n` scaled to length 1. A normal already of length 1 to rounding is kept as it is: dividing
// by a norm one ulp off moves its last bits, and cleaning twice must change nothing (such bits
// are enough to move a skeleton).
Vec3 unit(const Vec3& n) {
  const double norm = n.stableNorm();
  return std::abs(norm - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon() ? n : n / norm;
}

bool has_normal(const Vec3& n) { return n.allFinite() && n.stableNorm() > 0.0; }

constexpr double kNoNormal = std::numeric_limits<double>::quiet_NaN();

// A point's index; 32 bits (CleanReport::kept's) halve what cleaning holds besides the points.
using Index = int;
// Marks a point dropped or merged away (CleanReport::kept has none of them).
constexpr Index kDropped = -1;

using Face = std::array<int, 3>;

// Indices of the points with finite coordinates; throws InvalidInput for an infinite or absurd
// one. Counts the NaN points and the missing normals of the others.
std::vector<Index> finite_points(const SurfaceInput& surface, CleanReport& report) {
  const auto& points = surface.points;
  const bool with_normals = surface.has_normals();
  std::vector<Index> usable;
  usable.reserve(points.size());
  for (Index i = 0; i < static_cast<Index>(points.size()); ++i) {
    for (int c = 0; c < 3; ++c)
      if (std::isinf(points[i][c]) || std::abs(points[i][c]) > kMaxCoordinate) {
        std::ostringstream problem;
        problem << "point " << i << ": coordinate " << points[i][c]
                << " out of range (must be finite and at most 1e150 in magnitude)";
        throw InvalidInput(problem.str());
      }
    if (!points[i].allFinite()) {
      ++report.non_finite_points;
      continue;
    }
    usable.push_back(i);
    if (with_normals && !has_normal(surface.normals[i])) ++report.missing_normals;
  }
  return usable;
}

// A hash of a point's coordinates (their bits: -0 taken as 0, which equals it), whose high bits
// sort the points so that equal ones come together.
std::uint64_t place_hash(const Vec3& p) {
  std::uint64_t hash = 0;
  for (int c = 0; c < 3; ++c) {
    const double value = p[c] + 0.0;
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    hash = (hash ^ bits) * 0x9e3779b97f4a7c15ull;  // splitmix64's mixing after each coordinate
    hash ^= hash >> 31;
  }
  return hash;
}

// For every point, the first of the usable points at the same place (kDropped: not usable), and
// the duplicates counted. The points are sorted by one 64-bit key, the high bits of their
// place's hash above their index (a radix sort: sorting millions of points by coordinates took
// seconds), so that each run of equal hashes lists its points by index and the first one at
// each place in it is its representative. `box_diagonal` is the squared diagonal of the usable
// points' bounding box.
std::vector<Index> representatives(const std::vector<Vec3>& points,
                                   const std::vector<Index>& usable, CleanReport& report,
                                   double& box_diagonal) {
  constexpr int kIndexBits = 31;
  constexpr std::uint64_t kIndexMask = (std::uint64_t{1} << kIndexBits) - 1;
  std::vector<Index> representative(points.size(), kDropped);
  std::vector<std::uint64_t> keys;
  keys.reserve(usable.size());
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = -low;
  for (const Index i : usable) {
    keys.push_back((place_hash(points[i]) & ~kIndexMask) | static_cast<std::uint64_t>(i));
    low = low.cwiseMin(points[i]);
    high = high.cwiseMax(points[i]);
  }
  box_diagonal = (high - low).squaredNorm();
  internal::radix_sort(keys);
  std::vector<Index> places;  // the representatives met in the current run
  for (std::size_t first = 0, last = 0; first < keys.size(); first = last) {
    places.clear();
    for (last = first;
         last < keys.size() && (keys[last] >> kIndexBits) == (keys[first] >> kIndexBits); ++last) {
      const auto i = static_cast<Index>(keys[last] & kIndexMask);
      const auto same = std::find_if(places.begin(), places.end(),
                                     [&](Index place) { return points[place] == points[i]; });
      representative[i] = same == places.end() ? i : *same;
      if (same == places.end())
        places.push_back(i);
      else
        ++report.duplicate_points;
    }
  }
  return representative;
}

// The faces on representatives, without those that lose a corner, repeat one or have (almost)
// no area; `referenced` marks the corners of the faces kept.
std::vector<Face> kept_faces(const SurfaceInput& surface, const std::vector<Index>& representative,
                             double min_area, CleanReport& report, std::vector<bool>& referenced) {
  const auto& points = surface.points;
  const std::size_t count = points.size();
  std::vector<Face> faces;
  referenced.assign(count, false);
  for (const Face& face : surface.faces) {
    Face corners{};
    bool degenerate = false;
    for (int c = 0; c < 3; ++c) {
      corners[c] = face[c] >= 0 && static_cast<std::size_t>(face[c]) < count
                       ? representative[face[c]]
                       : kDropped;
      degenerate = degenerate || corners[c] == kDropped;
    }
    degenerate = degenerate || corners[0] == corners[1] || corners[1] == corners[2] ||
                 corners[0] == corners[2] ||
                 0.5 * (points[corners[1]] - points[corners[0]])
                             .cross(points[corners[2]] - points[corners[0]])
                             .norm() <
                     min_area;
    if (degenerate) {
      ++report.degenerate_faces;
      continue;
    }
    faces.push_back(corners);
    for (Index corner : corners) referenced[corner] = true;
  }
  return faces;
}

}  // namespace

CleanReport clean_surface(SurfaceInput& surface) {
  CleanReport report;
  const std::size_t count = surface.points.size();
  const bool with_normals = surface.has_normals();
  if (with_normals && surface.normals.size() != count)
    throw InvalidInput(std::to_string(surface.normals.size()) + " normals for " +
                       std::to_string(count) + " points");
  const bool with_density = !surface.density.empty();
  if (with_density && surface.density.size() != count)
    throw InvalidInput(std::to_string(surface.density.size()) + " density values for " +
                       std::to_string(count) + " points");
  if (count > static_cast<std::size_t>(std::numeric_limits<Index>::max()))
    throw InvalidInput(std::to_string(count) + " points: at most " +
                       std::to_string(std::numeric_limits<Index>::max()) + " are supported");
  std::vector<Index> usable = finite_points(surface, report);
  const std::size_t usable_count = usable.size();
  double box_diagonal = 0.0;
  const std::vector<Index> representative =
      representatives(surface.points, usable, report, box_diagonal);
  std::vector<Index>().swap(usable);
  const double min_area = usable_count == 0 ? 0.0 : 1e-14 * box_diagonal;
  std::vector<bool> referenced;
  std::vector<Face> faces = kept_faces(surface, representative, min_area, report, referenced);

  // A merged point carries the mean density of its duplicates.
  if (with_density && report.duplicate_points > 0) {
    const std::vector<double> merged =
        internal::mean_density_by_group(surface.density, representative, count, 0.0);
    for (Index i = 0; i < static_cast<Index>(count); ++i)
      if (representative[i] == i) surface.density[i] = merged[i];
  }
  // The points kept move down in place (a point's new place is never after its old one): a big
  // cloud is never held twice.
  const bool mesh = surface.is_mesh();
  std::vector<Index> new_index(mesh ? count : 0, kDropped);
  report.kept.reserve(usable_count - report.duplicate_points);
  Index kept = 0;
  for (Index i = 0; i < static_cast<Index>(count); ++i) {
    if (representative[i] != i) continue;
    if (mesh && !referenced[i]) {
      ++report.unused_points;
      continue;
    }
    if (mesh) new_index[i] = kept;
    report.kept.push_back(i);
    surface.points[kept] = surface.points[i];
    if (with_normals)
      surface.normals[kept] =
          has_normal(surface.normals[i]) ? unit(surface.normals[i]) : Vec3::Constant(kNoNormal);
    if (with_density) surface.density[kept] = surface.density[i];
    ++kept;
  }
  surface.points.resize(kept);
  surface.normals.resize(with_normals ? kept : 0);
  surface.density.resize(with_density ? kept : 0);
  // Not one normal given: a plain cloud.
  if (with_normals && report.missing_normals == usable_count) {
    surface.normals.clear();
    report.missing_normals = 0;
  }
  for (Face& corners : faces)
    for (Index& corner : corners) corner = new_index[corner];
  surface.faces = std::move(faces);
  return report;
}

MeshDefects mesh_defects(const std::vector<std::array<int, 3>>& faces) {
  struct Use {
    int low, high;  // the edge's vertices, low < high
    bool forward;   // the face runs from low to high
  };
  // Uses bucketed by their low vertex, then sorted within each bucket (a few uses each): a sort
  // of all of them took ~20 ms on a 73 000-face mesh.
  int vertices = 0;
  for (const auto& face : faces)
    for (int v : face) {
      if (v < 0) throw InvalidInput("mesh_defects: negative vertex index " + std::to_string(v));
      vertices = std::max(vertices, v + 1);
    }
  std::vector<int> offsets(vertices + 1, 0);
  for (const auto& face : faces)
    for (int c = 0; c < 3; ++c) ++offsets[std::min(face[c], face[(c + 1) % 3]) + 1];
  for (int v = 0; v < vertices; ++v) offsets[v + 1] += offsets[v];
  std::vector<Use> uses(3 * faces.size());
  std::vector<int> filled(offsets.begin(), offsets.end() - 1);
  for (const auto& face : faces)
    for (int c = 0; c < 3; ++c) {
      const int a = face[c], b = face[(c + 1) % 3];
      uses[filled[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), a < b};
    }
  for (int v = 0; v < vertices; ++v)
    std::sort(uses.begin() + offsets[v], uses.begin() + offsets[v + 1],
              [](const Use& x, const Use& y) { return x.high < y.high; });
  MeshDefects defects;
  for (std::size_t first = 0, last = 0; first < uses.size(); first = last) {
    while (last < uses.size() && uses[last].low == uses[first].low &&
           uses[last].high == uses[first].high)
      ++last;
    const std::size_t count = last - first;
    if (count == 1) ++defects.boundary_edges;
    if (count > 2) ++defects.non_manifold_edges;
    if (count == 2 && uses[first].forward == uses[first + 1].forward) ++defects.misoriented_edges;
  }
  return defects;
}

}  // namespace vmas
