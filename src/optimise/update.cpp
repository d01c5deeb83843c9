#include "optimise/update.hpp"

#include <Eigen/Dense>
#include <string>

#include "optimise/partition.hpp"
#include "vmas/error.hpp"

namespace vmas {

void UpdateOptions::validate() const {
  if (max_iterations < 1 || max_iterations > 1000)
    throw InvalidOption("max_iterations", "must be between 1 and 1000 (got " +
                                              std::to_string(max_iterations) + ")");
  if (!(step_tolerance >= 0.0 && step_tolerance < 1.0))
    throw InvalidOption("step_tolerance", "must be in [0, 1) (got " +
                        std::to_string(step_tolerance) + ")");
}

double cluster_energy(const Shape& shape, const std::vector<int>& members, const Sphere& sphere,
                      double lambda) {
  double energy = 0.0;
  for (int v : members) energy += vertex_energy(shape, v, sphere, lambda);
  return energy;
}

namespace {

// F(s) of one cluster, using the summed quadric for the SQEM part. When `hessian` is given, also
// the normal equations of the step from s: the Euclidean residuals ‖p−q‖ − r linearised with the
// unit directions u = (p − q)/‖p − q‖ frozen, i.e. ∇[½sᵀAs − bᵀs + λΣA(v)(uᵀp − ũᵀs)²] = 0 with
// ũ = (u, 1). kWeighted: each vertex's term times Shape::error_weight (a density; a template
// parameter so that the loop without one stays as tight as it was).
template <bool kNormalEquations, bool kWeighted>
double evaluate(const Shape& shape, const std::vector<int>& members, const Sqem& cluster_quadric,
                const Vec4& s, double lambda, Eigen::Matrix4d* hessian, Vec4* rhs) {
  const Vec3 center = s.head<3>();
  double euclidean = 0.0;
  // Local accumulators: through the pointers every term would be a load and a store.
  Eigen::Matrix4d h = cluster_quadric.A;
  Vec4 g = cluster_quadric.b;
  for (int v : members) {
    const Vec3 offset = shape.points[v] - center;
    const double length = offset.norm();
    const double area = kWeighted ? shape.area[v] * shape.error_weights[v] : shape.area[v];
    euclidean += area * (length - s.w()) * (length - s.w());
    // A sample at the centre gives no direction.
    if (!kNormalEquations || !(length > 0.0)) continue;
    const Vec3 u = offset / length;
    const Vec4 direction(u.x(), u.y(), u.z(), 1.0);
    const double weight = 2.0 * lambda * area;
    h.noalias() += weight * direction * direction.transpose();
    g.noalias() += (weight * u.dot(shape.points[v])) * direction;
  }
  if (kNormalEquations) {
    *hessian = h;
    *rhs = g;
  }
  return cluster_quadric(s) + lambda * euclidean;
}

double evaluate(const Shape& shape, const std::vector<int>& members, const Sqem& cluster_quadric,
                const Vec4& s, double lambda, Eigen::Matrix4d* hessian, Vec4* rhs) {
  if (!shape.error_weights.empty())
    return hessian
               ? evaluate<true, true>(shape, members, cluster_quadric, s, lambda, hessian, rhs)
               : evaluate<false, true>(shape, members, cluster_quadric, s, lambda, nullptr, nullptr);
  return hessian
             ? evaluate<true, false>(shape, members, cluster_quadric, s, lambda, hessian, rhs)
             : evaluate<false, false>(shape, members, cluster_quadric, s, lambda, nullptr, nullptr);
}

}  // namespace

Sphere fit_sphere(const Shape& shape, const std::vector<int>& members, const Sphere& initial,
                  double lambda, const UpdateOptions& options) {
  if (members.empty()) return initial;
  // With a density, each vertex's energy counts by its weight (docs/design.md, "Density").
  Sqem cluster_quadric;
  if (shape.error_weights.empty()) {
    for (int v : members) cluster_quadric += shape.quadric[v];
  } else {
    for (int v : members) cluster_quadric.add(shape.quadric[v], shape.error_weights[v]);
  }

  Vec4 current = to_vec4(initial);
  current.w() = std::max(current.w(), 0.0);
  Eigen::Matrix4d hessian;
  Vec4 rhs;
  double current_energy =
      evaluate(shape, members, cluster_quadric, current, lambda, &hessian, &rhs);
  const double step_tolerance = options.step_tolerance * shape.diagonal;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const Eigen::LDLT<Eigen::Matrix4d> solver(hessian);
    if (solver.info() != Eigen::Success) break;
    Vec4 target = solver.solve(rhs);
    if (!target.allFinite()) break;
    target.w() = std::max(target.w(), 0.0);

    // Backtrack towards the current sphere until the energy does not rise.
    const Vec4 step = target - current;
    const double step_length = step.norm();
    const bool last_iteration = iteration + 1 == options.max_iterations;
    double scale = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 12; ++halving, scale *= 0.5) {
      const Vec4 candidate = current + scale * step;
      // The normal equations are only needed if accepting this candidate lets the loop go on.
      const bool final_step = last_iteration || scale * step_length < step_tolerance;
      Eigen::Matrix4d next_hessian;
      Vec4 next_rhs;
      const double energy =
          evaluate(shape, members, cluster_quadric, candidate, lambda,
                   final_step ? nullptr : &next_hessian, final_step ? nullptr : &next_rhs);
      if (energy <= current_energy) {
        current = candidate;
        current_energy = energy;
        if (!final_step) {
          hessian = next_hessian;
          rhs = next_rhs;
        }
        accepted = true;
        break;
      }
    }
    if (!accepted || scale * step_length < step_tolerance) break;
  }
  return to_sphere(current);
}

}  // namespace vmas
