#pragma once
// Shape partitioning (paper §3.2): every vertex joins the sphere minimising
// E_v(m) = Q_v(m) + λ·A(v)·(‖p_v − q‖ − r)²  (eq. 8).
#include <vector>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// λ·A(v)·d_v(m)² — the point–sphere term (eq. 4/6) alone; a lower bound of E_v(m).
inline double euclidean_energy(const Shape& shape, int v, const Sphere& m, double lambda) {
  const double d = (shape.points[v] - m.center).norm() - m.radius;
  return lambda * shape.area[v] * d * d;
}

// The same sphere, bit for bit.
inline bool same_sphere(const Sphere& a, const Sphere& b) {
  return a.center == b.center && a.radius == b.radius;
}

// E_v(m) of eq. 8.
inline double vertex_energy(const Shape& shape, int v, const Sphere& m, double lambda) {
  return shape.quadric[v](m) + euclidean_energy(shape, v, m, lambda);
}

// Assigns every vertex to its best sphere (ties go to the lower index) and stores its energy.
// Exact: spheres are skipped only when the Euclidean lower bound alone already exceeds the best
// energy found: for groups of blocks of nearby vertices (shape.blocks) at once, then per block,
// then per vertex. Parallel over groups; the result does not depend on the thread count.
// `energies_current`: `energies` already hold E_v of each vertex's labelled sphere (they are not
// recomputed then). `partitioned` (with energies_current): the spheres that `labels` were the
// best of; a group of blocks none of whose vertices' spheres changed since, and near which no
// changed sphere passes, keeps its labels (every other sphere lost to them before).
void partition(const Shape& shape, const std::vector<Sphere>& spheres, double lambda,
               std::vector<int>& labels, std::vector<double>& energies,
               bool energies_current = false, const std::vector<Sphere>* partitioned = nullptr);

}  // namespace vmas
