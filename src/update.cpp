#include "update.hpp"

#include <Eigen/Dense>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <string>

#include "partition.hpp"
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

// Distances and unit directions from the centre to the members, two members at a time where
// SSE2 is (packed square roots and divisions, each rounded as the scalar ones: the same values).
struct MemberDirections {
  double length[2], u[2][3];
};

inline void directions_of(const Vec3& a, const Vec3& b, const Vec3& center, MemberDirections& out) {
#ifdef __SSE2__
  const __m128d dx = _mm_sub_pd(_mm_set_pd(b.x(), a.x()), _mm_set1_pd(center.x()));
  const __m128d dy = _mm_sub_pd(_mm_set_pd(b.y(), a.y()), _mm_set1_pd(center.y()));
  const __m128d dz = _mm_sub_pd(_mm_set_pd(b.z(), a.z()), _mm_set1_pd(center.z()));
  // Eigen's squaredNorm of a 3-vector: (x² + y²) + z².
  const __m128d length = _mm_sqrt_pd(
      _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz)));
  alignas(16) double ux[2], uy[2], uz[2];
  _mm_store_pd(ux, _mm_div_pd(dx, length));
  _mm_store_pd(uy, _mm_div_pd(dy, length));
  _mm_store_pd(uz, _mm_div_pd(dz, length));
  _mm_storeu_pd(out.length, length);
  for (int k = 0; k < 2; ++k) {
    out.u[k][0] = ux[k];
    out.u[k][1] = uy[k];
    out.u[k][2] = uz[k];
  }
#else
  const Vec3* points[2] = {&a, &b};
  for (int k = 0; k < 2; ++k) {
    const Vec3 offset = *points[k] - center;
    out.length[k] = offset.norm();
    for (int c = 0; c < 3; ++c) out.u[k][c] = offset[c] / out.length[k];
  }
#endif
}

// F(s) of one cluster, using the summed quadric for the SQEM part. When `hessian` is given, also
// the normal equations of the step from s: the Euclidean residuals ‖p−q‖ − r linearised with the
// unit directions u = (p − q)/‖p − q‖ frozen, i.e. ∇[½sᵀAs − bᵀs + λΣA(v)(uᵀp − ũᵀs)²] = 0 with
// ũ = (u, 1).
template <bool kNormalEquations>
double evaluate(const Shape& shape, const std::vector<int>& members, const Sqem& cluster_quadric,
                const Vec4& s, double lambda, Eigen::Matrix4d* hessian, Vec4* rhs) {
  const Vec3 center = s.head<3>();
  double euclidean = 0.0;
  // Local accumulators, one scalar per entry (h[i][j] += (w u_i) u_j, u_3 = 1, g[i] += (w u·p) u_i,
  // in member order, as the matrix expressions would, products by u_3 left out): held in
  // registers, where a 4×4 matrix of Eigen's was spilled and reloaded for every member.
  double h[4][4], g[4];
  for (int i = 0; i < 4; ++i) {
    g[i] = cluster_quadric.b[i];
    for (int j = 0; j < 4; ++j) h[i][j] = cluster_quadric.A(i, j);
  }
  const auto add = [&](int v, double length, const double (&u)[3]) {
    euclidean += shape.area[v] * (length - s.w()) * (length - s.w());
    // A sample at the centre gives no direction.
    if (!kNormalEquations || !(length > 0.0)) return;
    const double weight = 2.0 * lambda * shape.area[v];
    const double wu[3] = {weight * u[0], weight * u[1], weight * u[2]};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) h[i][j] += wu[i] * u[j];
      h[i][3] += wu[i];
      h[3][i] += weight * u[i];
    }
    h[3][3] += weight;
    const Vec3& p = shape.points[v];
    const double along = weight * ((u[0] * p.x() + u[1] * p.y()) + u[2] * p.z());
    for (int i = 0; i < 3; ++i) g[i] += along * u[i];
    g[3] += along;
  };
  const std::size_t count = members.size();
  MemberDirections pair;
  std::size_t k = 0;
  for (; k + 1 < count; k += 2) {
    const int a = members[k], b = members[k + 1];
    directions_of(shape.points[a], shape.points[b], center, pair);
    add(a, pair.length[0], pair.u[0]);
    add(b, pair.length[1], pair.u[1]);
  }
  if (k < count) {
    const int a = members[k];
    directions_of(shape.points[a], shape.points[a], center, pair);
    add(a, pair.length[0], pair.u[0]);
  }
  if (kNormalEquations) {
    for (int i = 0; i < 4; ++i) {
      (*rhs)[i] = g[i];
      for (int j = 0; j < 4; ++j) (*hessian)(i, j) = h[i][j];
    }
  }
  return cluster_quadric(s) + lambda * euclidean;
}

double evaluate(const Shape& shape, const std::vector<int>& members, const Sqem& cluster_quadric,
                const Vec4& s, double lambda, Eigen::Matrix4d* hessian, Vec4* rhs) {
  return hessian ? evaluate<true>(shape, members, cluster_quadric, s, lambda, hessian, rhs)
                 : evaluate<false>(shape, members, cluster_quadric, s, lambda, nullptr, nullptr);
}

}  // namespace

Sphere fit_sphere(const Shape& shape, const std::vector<int>& members, const Sphere& initial,
                  double lambda, const UpdateOptions& options) {
  if (members.empty()) return initial;
  Sqem cluster_quadric;
  for (int v : members) cluster_quadric += shape.quadric[v];

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
