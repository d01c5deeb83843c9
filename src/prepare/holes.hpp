#pragma once
// Holes of a sampled surface: where a scan stops (the side a scanned object stood on, an
// occlusion, a cut), the points of the rim see all their neighbours on one side.
#include <vector>

#include "prepare/prepare.hpp"

namespace vmas {

// The holes of a cloud with oriented normals, widest first. A point is on a rim when, seen
// along its normal, the directions to its 16 nearest neighbours (24 when `smoothed`: the
// smoothing leaves the density uneven) leave a gap wider than 150°,
// none of them lies on an opposite sheet (a fold, the edge of a thin part) and they spread like
// a flat patch (not a line of points, not a thin part sampled around). Rim points within 1.5
// neighbourhood reaches of one another form a rim; a rim of at least 10 points, 3 median
// neighbourhood reaches wide, is a hole. A clean random sampling has such gaps at scattered
// points only. Strong noise hides small holes. Empty for no more points than neighbours.
std::vector<Hole> find_holes(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                             bool smoothed = false);

// The positions of a hole's rim points among `points` (those find_holes was given).
std::vector<Vec3> rim_points(const Hole& hole, const std::vector<Vec3>& points);

// The plane of a hole's rim: its centre, its unit normal towards the outside of `cloud` (the side
// fewer of its points lie on), and the rim's largest distance from the centre within the plane.
struct RimPlane {
  Vec3 centre = Vec3::Zero();
  Vec3 outward = Vec3::UnitZ();
  double radius = 0.0;
};
RimPlane rim_plane(const std::vector<Vec3>& rim, const std::vector<Vec3>& cloud);

// Points that close a hole as a solid closes it: a lid over its rim, an even grid `spacing` apart
// (the rim points' median distance to their nearest when not positive; coarser when more than
// `at_most` points would be needed) on the rim's plane, out to the rim as seen from the centre
// (the farthest rim point in each of 64 sectors around it), lifted off the plane as a cone from
// the centre to that point, so that the lid meets a rim that is not flat.
std::vector<Vec3> lid_points(const std::vector<Vec3>& rim, const RimPlane& plane, double spacing,
                             int at_most = 20000);
// The lids of all `holes` of `points` (a cloud, `spacing` apart), 40 000 points at most in all.
std::vector<Vec3> lid_points(const std::vector<Hole>& holes, const std::vector<Vec3>& points,
                             double spacing);

}  // namespace vmas
