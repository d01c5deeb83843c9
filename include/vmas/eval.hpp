#pragma once
// Reconstruction error of a medial mesh (paper §4, Table 1). The reconstruction is the union of
// the medial primitives: every sphere, the convex hull of the two spheres of every edge (a round
// cone) and the convex hull of the three spheres of every face (a slab: three cones plus the two
// triangles tangent to all three spheres). Face edges count as edges even when not listed.
//   surface -> medial: for every input point plus area-weighted random surface samples, the
//     smallest unsigned distance to the boundary of any sphere, cone or tangent triangle;
//   medial -> surface: for samples on every primitive boundary that lie inside no other
//     primitive, the distance to the input mesh (to the nearest input point for a cloud, or to
//     the nearest of its points' tangent discs: EvalOptions::cloud_as_discs), or to the nearest
//     of EvalOptions::lid_points when nearer.
// ε (hausdorff) is the larger of the two maxima; percent() expresses it relative to the input's
// bounding-box diagonal as the paper does.
#include <cstddef>
#include <memory>
#include <vector>

#include "vmas/options.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

struct EvalResult {
  double diagonal = 0.0;  // bounding-box diagonal of the input; every length below is absolute
  double surface_to_medial_max = 0.0;
  double surface_to_medial_mean = 0.0;
  double medial_to_surface_max = 0.0;
  double medial_to_surface_mean = 0.0;
  double hausdorff = 0.0;                       // max of the two one-sided maxima
  Vec3 surface_to_medial_worst = Vec3::Zero();  // where each one-sided maximum was found:
  Vec3 medial_to_surface_worst = Vec3::Zero();  //   a surface sample, a boundary sample
  std::size_t surface_sample_count = 0;         // input points + random surface samples
  std::size_t boundary_sample_count = 0;  // visible uniform samples on the primitives' boundaries
  // Surface -> medial distance of every input point (for colour maps).
  std::vector<double> vertex_error;
  // Medial -> surface: the boundary_sample_count visible samples, boundary_spacing apart, and
  // the distance of each to the input. Their mean is medial_to_surface_mean; their maximum is at
  // most medial_to_surface_max (refined around them) and less than a spacing below it.
  std::vector<Vec3> boundary_samples;
  std::vector<double> boundary_error;

  double percent(double length) const { return 100.0 * length / diagonal; }
};

// evaluate() for many medial meshes of one shape: the shape's samples and its distance structure
// are built once, and what was measured of primitives that come back unchanged (same spheres)
// is re-used. Results are those of evaluate(). Keeps a reference to `shape`; one call at a time
// (calls update what it keeps).
class Evaluator {
 public:
  // Throws as evaluate() does for the shape and the options.
  Evaluator(const SurfaceInput& shape, const EvalOptions& options = {});
  ~Evaluator();
  Evaluator(const Evaluator&) = delete;
  Evaluator& operator=(const Evaluator&) = delete;
  // Throws as evaluate() does for the medial mesh. What it measured of each primitive is re-used
  // for the same primitive in the next call (results do not depend on what was measured before).
  EvalResult operator()(const MedialMesh& medial);
  // Sets aside what the last call measured, and puts it back: a caller that returns to an earlier
  // medial mesh (a refinement undoing a move) measures the next one as fast as if it had measured
  // nothing since.
  void keep_memory();
  void restore_memory();
  // The distance of each query to the shape, as the medial -> surface side measures it (a
  // mesh's faces; a cloud's points, or their tangent discs with cloud_as_discs; lid_points).
  std::vector<double> distances_to_shape(const std::vector<Vec3>& queries) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// How a reconstruction meets the openings of a cloud (a scan's cut, the side it stood on). Its
// two-sided error cannot be the measure there: a union of spheres is a solid, whose surface
// across an opening lies about the opening's radius from any data. What can be asked is that it
// covers the data (EvalResult::surface_to_medial_max) and does not bulge out through the opening.
struct OpeningReach {
  int openings = 0;    // holes of the cloud, as vmas skeletonize finds them (prepared by default)
  double reach = 0.0;  // absolute: the farthest the reconstruction's boundary samples over an
                       // opening lie past the plane of its rim (0 when none does)
};

// The openings of `cloud` (a point cloud: none for a mesh) and how far `evaluated`'s uniform
// boundary samples (evaluate() with maxima_only off) reach past them. An opening's plane is
// fitted to its rim points; its outside is the side holding fewer of the cloud's points; a
// sample is over the opening when it projects onto the plane within the rim's radius.
OpeningReach opening_reach(const SurfaceInput& cloud, const EvalResult& evaluated);

// Throws InvalidInput when the shape has no point or a face index out of range, or when the
// medial mesh is empty, has an index out of range or repeated within an element, or a radius
// that is negative or not finite.
EvalResult evaluate(const SurfaceInput& shape, const MedialMesh& medial,
                    const EvalOptions& options = {});

// The Betti numbers over Z/2 of `medial` as a simplicial complex (MedialTopology: its spheres,
// its edges and the edges of its triangles, its triangles; a triangle listed twice counts once,
// as a duplicate).
MedialTopology medial_topology(const MedialMesh& medial);
// The genus of each piece of a closed triangle mesh (SurfaceGenus).
// `defects`: mesh_defects(mesh.faces), which the caller has already (ignored for a cloud).
SurfaceGenus surface_genus(const SurfaceInput& mesh, const MeshDefects& defects);

}  // namespace vmas

#pragma GCC visibility pop
