#include "vmas/partition.hpp"

#include <limits>

#include "vmas/error.hpp"

namespace vmas {

void partition(const Shape& shape, const std::vector<Sphere>& spheres, double lambda,
               std::vector<int>& labels, std::vector<double>& energies) {
  if (spheres.empty()) throw InvalidInput("cannot partition a shape among zero spheres");
  const int n = shape.size();
  const int count = static_cast<int>(spheres.size());
  labels.resize(n, 0);
  energies.resize(n);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < n; ++v) {
    // Start from the previous label: it is usually still the best, which makes the bound bite.
    int best = (labels[v] >= 0 && labels[v] < count) ? labels[v] : 0;
    double best_energy = vertex_energy(shape, v, spheres[best], lambda);
    for (int m = 0; m < count; ++m) {
      if (m == best) continue;
      const double bound = euclidean_energy(shape, v, spheres[m], lambda);
      if (bound > best_energy || (bound == best_energy && m > best)) continue;
      const double energy = bound + shape.quadric[v](spheres[m]);
      if (energy < best_energy || (energy == best_energy && m < best)) {
        best = m;
        best_energy = energy;
      }
    }
    labels[v] = best;
    energies[v] = best_energy;
  }
}

}  // namespace vmas
