#include "optimise/partition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "vmas/error.hpp"

namespace vmas {

namespace {

// Slack on the block bound, far above the rounding of the distances involved: a sphere is dropped
// for a block only when every vertex of the block would have skipped it anyway.
constexpr double kRelativeSlack = 1e-6;
constexpr double kAbsoluteSlack = 1e-9;

// Consecutive blocks (neighbours in the median-split tree) are first tested as one group, so that
// each block only tests the spheres that survived for its group.
constexpr int kBlocksPerGroup = 8;

// The spheres of `from` whose surface may pass within `reach` of the ball (center, radius).
void near_spheres(const std::vector<Sphere>& spheres, const Vec3& center, double radius,
                  double reach, const std::vector<int>& from, std::vector<int>& near) {
  near.clear();
  for (int m : from) {
    const double distance = (center - spheres[m].center).norm();
    const double gap = std::abs(distance - spheres[m].radius) - radius;
    const double slack =
        kRelativeSlack * reach + kAbsoluteSlack * (distance + spheres[m].radius + radius);
    if (gap <= reach + slack) near.push_back(m);
  }
}

// Vertex v's best sphere: the exhaustive scan in sphere order, restricted to the candidates,
// from its label and energy as they are.
void assign_best(const Shape& shape, const std::vector<Sphere>& spheres, double lambda,
                 const std::vector<int>& candidates, int v, int& label, double& energy) {
  for (int m : candidates) {
    if (m == label) continue;
    const double bound = euclidean_energy(shape, v, spheres[m], lambda);
    if (bound > energy || (bound == energy && m > label)) continue;
    const double candidate = bound + shape.quadric[v](spheres[m]);
    if (candidate < energy || (candidate == energy && m < label)) {
      label = m;
      energy = candidate;
    }
  }
}

// The spheres other than those of `partitioned` (by index; new ones too), as a mask and a list.
void changed_spheres(const std::vector<Sphere>& spheres, const std::vector<Sphere>& partitioned,
                     std::vector<char>& mask, std::vector<int>& list) {
  mask.assign(spheres.size(), 0);
  for (std::size_t m = 0; m < spheres.size(); ++m) {
    if (m < partitioned.size() && same_sphere(spheres[m], partitioned[m])) continue;
    mask[m] = 1;
    list.push_back(static_cast<int>(m));
  }
}

}  // namespace

void partition(const Shape& shape, const std::vector<Sphere>& spheres, double lambda,
               std::vector<int>& labels, std::vector<double>& energies, bool energies_current,
               const std::vector<Sphere>* partitioned) {
  if (spheres.empty()) throw InvalidInput("cannot partition a shape among zero spheres");
  const int n = shape.size();
  const VertexBlocks& blocks = shape.blocks;
  if (static_cast<int>(blocks.vertices.size()) != n)
    throw InvalidInput("the shape has no vertex blocks (build it with build_shape)");
  const int count = static_cast<int>(spheres.size());
  if (labels.size() != static_cast<std::size_t>(n) || energies.size() != labels.size())
    energies_current = false;
  labels.resize(n, 0);
  energies.resize(n);
  std::vector<int> all(count);
  std::iota(all.begin(), all.end(), 0);
  std::vector<char> changed;
  std::vector<int> changed_list;
  if (energies_current && partitioned) changed_spheres(spheres, *partitioned, changed, changed_list);
  // When every sphere changed (a run's steps) no group can be passed over: no test either.
  const bool incremental = !changed.empty() && static_cast<int>(changed_list.size()) < count;
  const int groups = (blocks.size() + kBlocksPerGroup - 1) / kBlocksPerGroup;
#pragma omp parallel
  {
    std::vector<int> group_candidates, candidates;
    std::vector<double> reaches;
    group_candidates.reserve(count);
    candidates.reserve(count);
#pragma omp for schedule(dynamic)
    for (int group = 0; group < groups; ++group) {
      const int begin = group * kBlocksPerGroup;
      const int end = std::min(begin + kBlocksPerGroup, blocks.size());
      // Start from the previous label: it is usually still the best, which makes the bound bite.
      // A sphere whose surface stays farther than `reach` from every vertex of a block has a
      // Euclidean term above each of those energies, so the exhaustive scan would skip it.
      reaches.assign(end - begin, 0.0);
      Vec3 center = Vec3::Zero();
      bool touched = !incremental;  // a vertex's sphere changed (or it has none)
      for (int b = begin; b < end; ++b) {
        double& reach = reaches[b - begin];
        for (int i = blocks.offsets[b]; i < blocks.offsets[b + 1]; ++i) {
          const int v = blocks.vertices[i];
          if (labels[v] < 0 || labels[v] >= count) {
            labels[v] = 0;
            energies[v] = vertex_energy(shape, v, spheres[0], lambda);
            touched = true;
          } else if (!energies_current) {
            energies[v] = vertex_energy(shape, v, spheres[labels[v]], lambda);
          } else if (incremental && changed[labels[v]]) {
            touched = true;
          }
          const double distance = std::sqrt(std::max(energies[v], 0.0) / (lambda * shape.area[v]));
          if (!(distance <= reach))
            reach = std::isnan(distance) ? std::numeric_limits<double>::infinity() : distance;
        }
        center += blocks.centers[b];
      }
      center /= end - begin;
      double radius = 0.0;  // of a ball around every block of the group
      for (int b = begin; b < end; ++b)
        radius = std::max(radius, (blocks.centers[b] - center).norm() + blocks.radii[b]);
      const double group_reach = *std::max_element(reaches.begin(), reaches.end());
      if (!touched) {
        near_spheres(spheres, center, radius, group_reach, changed_list, group_candidates);
        if (group_candidates.empty()) continue;
      }
      near_spheres(spheres, center, radius, group_reach, all, group_candidates);

      for (int b = begin; b < end; ++b) {
        near_spheres(spheres, blocks.centers[b], blocks.radii[b], reaches[b - begin],
                     group_candidates, candidates);
        for (int i = blocks.offsets[b]; i < blocks.offsets[b + 1]; ++i) {
          const int v = blocks.vertices[i];
          assign_best(shape, spheres, lambda, candidates, v, labels[v], energies[v]);
        }
      }
    }
  }
}

}  // namespace vmas
