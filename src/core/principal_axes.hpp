#pragma once
// The principal axes of a few points: the least-squares plane of a neighbourhood (its normal is
// the axis of least spread) and how far the points spread along each axis.
#include <Eigen/Eigenvalues>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

struct PrincipalAxes {
  Vec3 centroid = Vec3::Zero();
  Vec3 spread = Vec3::Zero();                          // scatter eigenvalues, ascending
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: the matching unit axes
  bool valid = false;                                  // the decomposition succeeded
  Vec3 normal() const { return axes.col(0); }
};

// Of points[i] for every i of `indices` (any range of ints, at least one).
template <typename Indices>
PrincipalAxes principal_axes(const std::vector<Vec3>& points, const Indices& indices) {
  PrincipalAxes fit;
  double count = 0.0;
  for (int i : indices) {
    fit.centroid += points[i];
    ++count;
  }
  fit.centroid /= count;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : indices) scatter += (points[i] - fit.centroid) * (points[i] - fit.centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  fit.valid = eigen.info() == Eigen::Success;
  if (fit.valid) {
    fit.spread = eigen.eigenvalues();
    fit.axes = eigen.eigenvectors();
  }
  return fit;
}

// The mean of all the points (at least one).
inline Vec3 centroid_of(const std::vector<Vec3>& points) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace internal
}  // namespace vmas
