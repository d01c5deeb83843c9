#pragma once
// Sphere update (paper §3.3, eq. 9–11): the sphere minimising
//   F(s) = Σ_{v∈C} Q_v(s) + λ Σ_{v∈C} A(v)(‖p_v − q‖ − r)²
// over one cluster, by Gauss–Newton with the unit directions u_v = (p_v − q)/‖p_v − q‖ frozen
// per step. A step that would raise F is halved until it does not, so F never increases.
#include <vector>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// F(s) for the cluster `members`.
double cluster_energy(const Shape& shape, const std::vector<int>& members, const Sphere& sphere,
                      double lambda);

// The refitted sphere, starting from `initial`; its radius is never negative.
Sphere fit_sphere(const Shape& shape, const std::vector<int>& members, const Sphere& initial,
                  double lambda, const UpdateOptions& options);

}  // namespace vmas
