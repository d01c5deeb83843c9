#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "prepare/prepare.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"

namespace vmas {

namespace {

// The plane of an opening's rim (input coordinates): its centre, its unit normal towards the
// outside, and the rim's largest distance from the centre within the plane.
struct RimPlane {
  Vec3 centre = Vec3::Zero();
  Vec3 outward = Vec3::UnitZ();
  double radius = 0.0;
};

RimPlane rim_plane(const std::vector<Vec3>& rim, const std::vector<Vec3>& cloud) {
  RimPlane plane;
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

}  // namespace

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
    std::vector<Vec3> rim;
    rim.reserve(hole.rim.size());
    for (int p : hole.rim) rim.push_back(report.frame.to_input(prepared.points[p]));
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
