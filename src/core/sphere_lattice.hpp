#pragma once
// Directions spread evenly over the unit sphere.
#include <cmath>

#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

// The i-th of n directions of the Fibonacci lattice: about one per 4π / n of the sphere's area.
inline Vec3 fibonacci_direction(int i, int n) {
  const double golden_angle = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  const double z = 1.0 - (2.0 * i + 1.0) / n;
  const double rho = std::sqrt(1.0 - z * z);
  const double phi = golden_angle * i;
  return Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
}

}  // namespace internal
}  // namespace vmas
