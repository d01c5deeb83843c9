#include "vmas/update.hpp"

#include <Eigen/Dense>
#include <string>

#include "vmas/error.hpp"
#include "vmas/partition.hpp"

namespace vmas {

void UpdateOptions::validate() const {
  if (max_iterations < 1 || max_iterations > 1000)
    throw InvalidOption("update iterations must be between 1 and 1000 (got " +
                        std::to_string(max_iterations) + ")");
  if (!(step_tolerance >= 0.0 && step_tolerance < 1.0))
    throw InvalidOption("update step tolerance must be in [0, 1) (got " +
                        std::to_string(step_tolerance) + ")");
}

double cluster_energy(const Shape& shape, const std::vector<int>& members, const Sphere& sphere,
                      double lambda) {
  double energy = 0.0;
  for (int v : members) energy += vertex_energy(shape, v, sphere, lambda);
  return energy;
}

Sphere fit_sphere(const Shape& shape, const std::vector<int>& members, const Sphere& initial,
                  double lambda, const UpdateOptions& options) {
  if (members.empty()) return initial;
  Sqem cluster_quadric;
  for (int v : members) cluster_quadric += shape.quadric[v];

  Vec4 current = to_vec4(initial);
  current.w() = std::max(current.w(), 0.0);
  double current_energy = cluster_energy(shape, members, to_sphere(current), lambda);
  const double step_tolerance = options.step_tolerance * shape.diagonal;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // Normal equations of the linearised objective: ∇ of ½sᵀAs − bᵀs + λΣA(uᵀp − vᵀs)².
    Eigen::Matrix4d hessian = cluster_quadric.A;
    Vec4 rhs = cluster_quadric.b;
    for (int v : members) {
      const Vec3 offset = shape.points[v] - current.head<3>();
      const double length = offset.norm();
      if (!(length > 0.0)) continue;  // a sample at the centre gives no direction
      const Vec3 u = offset / length;
      const Vec4 direction(u.x(), u.y(), u.z(), 1.0);
      const double weight = 2.0 * lambda * shape.area[v];
      hessian.noalias() += weight * direction * direction.transpose();
      rhs.noalias() += (weight * u.dot(shape.points[v])) * direction;
    }
    const Eigen::LDLT<Eigen::Matrix4d> solver(hessian);
    if (solver.info() != Eigen::Success) break;
    Vec4 target = solver.solve(rhs);
    if (!target.allFinite()) break;
    target.w() = std::max(target.w(), 0.0);

    // Backtrack towards the current sphere until the energy does not rise.
    const Vec4 step = target - current;
    double scale = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 12; ++halving, scale *= 0.5) {
      const Vec4 candidate = current + scale * step;
      const double energy = cluster_energy(shape, members, to_sphere(candidate), lambda);
      if (energy <= current_energy) {
        current = candidate;
        current_energy = energy;
        accepted = true;
        break;
      }
    }
    if (!accepted || scale * step.norm() < step_tolerance) break;
  }
  return to_sphere(current);
}

}  // namespace vmas
