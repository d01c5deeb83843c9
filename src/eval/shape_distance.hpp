#pragma once
// The input shape as the evaluator measures against it: its points plus random samples of its
// faces (surface -> medial), and the distance of any point to it (medial -> surface).
#include <optional>
#include <vector>

#include "core/kdtree.hpp"
#include "eval/bvh.hpp"
#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

// Throws InvalidInput when the shape has no point or a face index out of range.
void check_shape(const SurfaceInput& shape);

// Input points followed by `count` area-weighted random points of the mesh's surface.
std::vector<Vec3> surface_samples(const SurfaceInput& shape, int count, unsigned seed);

// Distance to the input: exact point-to-triangle distance for a mesh; for a cloud, to the nearest
// point, or with `discs` (and a normal at every point) to the nearest of the points' tangent
// discs (EvalOptions::cloud_as_discs); or to the nearest of `lid_points` (EvalOptions::lid_points)
// when nearer.
class ShapeDistance {
 public:
  ShapeDistance(const SurfaceInput& shape, bool discs, const std::vector<Vec3>& lid_points = {});

  // Exact distances, or for a query farther than `stop_below` from the input some distance below
  // it (see Bvh::nearest).
  std::vector<double> operator()(const std::vector<Vec3>& queries,
                                 double stop_below = -kInfinity) const;

 private:
  double distance(const Vec3& q, double stop_below, int& near_face) const;
  double input_distance(const Vec3& q, double stop_below, int& near_face) const;
  double disc_distance(const Vec3& q) const;

  const SurfaceInput& shape_;
  std::optional<KdTree> points_;
  std::optional<KdTree> lid_points_;
  std::vector<double> disc_radius_;  // per point, when measuring to discs
  std::vector<Box> boxes_;
  std::optional<Bvh> triangles_;  // refers to boxes_
};

}  // namespace internal
}  // namespace vmas
