#include "vmas/partition.hpp"

#include <cmath>
#include <limits>

#include "vmas/error.hpp"

namespace vmas {

namespace {

// Slack on the block bound, far above the rounding of the distances involved: a sphere is dropped
// for a block only when every vertex of the block would have skipped it anyway.
constexpr double kRelativeSlack = 1e-6;
constexpr double kAbsoluteSlack = 1e-9;

}  // namespace

void partition(const Shape& shape, const std::vector<Sphere>& spheres, double lambda,
               std::vector<int>& labels, std::vector<double>& energies) {
  if (spheres.empty()) throw InvalidInput("cannot partition a shape among zero spheres");
  const int n = shape.size();
  const VertexBlocks& blocks = shape.blocks;
  if (static_cast<int>(blocks.vertices.size()) != n)
    throw InvalidInput("the shape has no vertex blocks (build it with build_shape)");
  const int count = static_cast<int>(spheres.size());
  labels.resize(n, 0);
  energies.resize(n);
#pragma omp parallel
  {
    std::vector<int> candidates;
    candidates.reserve(count);
#pragma omp for schedule(dynamic, 4)
    for (int b = 0; b < blocks.size(); ++b) {
      const int* first = blocks.vertices.data() + blocks.offsets[b];
      const int* last = blocks.vertices.data() + blocks.offsets[b + 1];
      // Start from the previous label: it is usually still the best, which makes the bound bite.
      // A sphere whose surface stays farther than `reach` from every vertex of the block has a
      // Euclidean term above each of those energies, so the exhaustive scan would skip it.
      double reach = 0.0;
      for (const int* it = first; it != last; ++it) {
        const int v = *it;
        if (labels[v] < 0 || labels[v] >= count) labels[v] = 0;
        energies[v] = vertex_energy(shape, v, spheres[labels[v]], lambda);
        const double distance = std::sqrt(std::max(energies[v], 0.0) / (lambda * shape.area[v]));
        if (!(distance <= reach))
          reach = std::isnan(distance) ? std::numeric_limits<double>::infinity() : distance;
      }
      candidates.clear();
      for (int m = 0; m < count; ++m) {
        const double distance = (blocks.centers[b] - spheres[m].center).norm();
        const double gap = std::abs(distance - spheres[m].radius) - blocks.radii[b];
        const double slack = kRelativeSlack * reach +
                             kAbsoluteSlack * (distance + spheres[m].radius + blocks.radii[b]);
        if (gap <= reach + slack) candidates.push_back(m);
      }
      // The exhaustive scan in sphere order, restricted to the candidates.
      for (const int* it = first; it != last; ++it) {
        const int v = *it;
        int best = labels[v];
        double best_energy = energies[v];
        for (int m : candidates) {
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
  }
}

}  // namespace vmas
