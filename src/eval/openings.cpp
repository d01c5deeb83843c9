#include <algorithm>
#include <cmath>

#include "prepare/holes.hpp"
#include "prepare/prepare.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"

namespace vmas {

OpeningReach opening_reach(const SurfaceInput& cloud, const EvalResult& evaluated) {
  OpeningReach result;
  if (cloud.is_mesh()) return result;
  // The holes as a run finds them: on the points prepared as for a run (normals estimated and
  // oriented where the file has none, noise smoothed away).
  SurfaceInput prepared = cloud;
  clean_surface(prepared);
  PrepareReport report;
  try {
    report = prepare_surface(prepared, PrepareOptions{});
  } catch (const InvalidInput&) {
    return result;  // too few points for holes
  }
  result.openings = static_cast<int>(report.holes.size());
  for (const Hole& hole : report.holes) {
    std::vector<Vec3> rim = rim_points(hole, prepared.points);
    for (Vec3& p : rim) p = report.frame.to_input(p);
    const RimPlane plane = rim_plane(rim, cloud.points);
    for (const Vec3& q : evaluated.boundary_samples) {
      const Vec3 offset = q - plane.centre;
      const double past = offset.dot(plane.outward);
      if (!(past > result.reach)) continue;
      if ((offset - past * plane.outward).norm() <= plane.radius) result.reach = past;
    }
  }
  return result;
}

}  // namespace vmas
