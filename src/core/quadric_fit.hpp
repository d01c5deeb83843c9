#pragma once
// The least-squares quadric height field over the principal plane of a few points: a curved
// neighbourhood's surface (a sphere's cap, a finger's tip, a thin tube's side), which a plane
// would miss.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/principal_axes.hpp"
#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

struct QuadricFit {
  bool valid = false;
  Vec3 centroid, u, v, normal;
  Vec3 spread = Vec3::Zero();  // of the points along normal, v, u (PrincipalAxes::spread)
  Eigen::Matrix<double, 6, 1> coefficients;
  double residual_squares = 0.0;  // summed over the fitted points

  static Eigen::Matrix<double, 6, 1> terms(double x, double y) {
    Eigen::Matrix<double, 6, 1> t;
    t << 1.0, x, y, x * x, x * y, y * y;
    return t;
  }
  // Distance of p from the quadric along the plane's normal.
  double offset(const Vec3& p) const {
    const Vec3 d = p - centroid;
    return std::abs(d.dot(normal) - coefficients.dot(terms(d.dot(u), d.dot(v))));
  }
};

// Of points[i] for every i of `indices` (at least six, not all on one line for a valid fit).
inline QuadricFit fit_quadric(const std::vector<Vec3>& points, const std::vector<int>& indices) {
  QuadricFit quadric;
  const PrincipalAxes fit = principal_axes(points, indices);
  if (!fit.valid) return quadric;
  quadric.centroid = fit.centroid;
  quadric.spread = fit.spread;
  quadric.normal = fit.normal();
  quadric.u = fit.axes.col(2);
  quadric.v = fit.axes.col(1);
  Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  double height_squares = 0.0;
  for (int i : indices) {
    const Vec3 d = points[i] - quadric.centroid;
    const double h = d.dot(quadric.normal);
    const Eigen::Matrix<double, 6, 1> t = QuadricFit::terms(d.dot(quadric.u), d.dot(quadric.v));
    normal_matrix += t * t.transpose();
    rhs += h * t;
    height_squares += h * h;
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(normal_matrix);
  if (solver.info() != Eigen::Success) return quadric;
  quadric.coefficients = solver.solve(rhs);
  // Sum of squared residuals of the least-squares solution: hᵀh − cᵀ(Pᵀh).
  quadric.residual_squares = std::max(height_squares - quadric.coefficients.dot(rhs), 0.0);
  quadric.valid = true;
  return quadric;
}

}  // namespace internal
}  // namespace vmas
