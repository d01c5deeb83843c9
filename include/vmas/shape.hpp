#pragma once
// The shape as the method sees it (paper §3.1): positions, outward unit normals, per-vertex
// support area A(v), the diffused quadric Q_v of each vertex, and a symmetric neighbour graph
// (mesh edges, or the k-NN graph of a cloud, its pieces joined by their shortest bridges among
// the 16 nearest neighbours) used for cluster adjacency.
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "vmas/sqem.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

struct ShapeOptions {
  int k = 6;  // neighbours per point for clouds: the k-NN graph and the quadric diffusion (eq. 5)
  void validate() const;  // throws InvalidOption
};

// Vertices regrouped into spatially compact blocks (the leaves of a median-split tree): block b
// holds vertices[offsets[b] .. offsets[b+1]), all inside the ball (centers[b], radii[b]). Lets a
// stage bound a distance for a whole block at once.
struct VertexBlocks {
  std::vector<int> vertices;
  std::vector<int> offsets;
  std::vector<Vec3> centers;
  std::vector<double> radii;

  int size() const { return static_cast<int>(centers.size()); }
};

struct Shape {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;           // unit, outward
  std::vector<double> area;            // A(v) (eq. 4 and 6)
  std::vector<double> density;         // of each vertex (SurfaceInput::density; empty: uniform)
  double density_max = 0.0;            // the largest of them
  std::vector<double> error_weights;   // of each vertex: error_weight's (empty without a density)
  std::vector<Sqem> quadric;           // Q_v (eq. 5 and 7)
  std::vector<int> neighbour_offsets;  // CSR: neighbours of v are
  std::vector<int> neighbours;  //   neighbours[neighbour_offsets[v] .. neighbour_offsets[v+1])
  VertexBlocks blocks;
  bool is_mesh = false;
  double diagonal = 0.0;  // bounding-box diagonal: the unit of every relative length
  double total_area = 0.0;

  int size() const { return static_cast<int>(points.size()); }
  // The weight of an error at density d where spheres are placed: d⁴, so that a cluster's RMS
  // error counts d² times (docs/design.md, "Density").
  static double density_weight(double d) { return (d * d) * (d * d); }
  // ... of vertex v's error, relative to the densest vertex's (1 without a density, and for a
  // uniform one: such a field changes nothing to the bit): what the fits, the split seeds and
  // the refinement's removals weigh by.
  double error_weight(int v) const { return error_weights.empty() ? 1.0 : error_weights[v]; }
  // Sets `density` (checked by the caller: vmas::check_density), `density_max` and
  // `error_weights`.
  void set_density(std::vector<double> values) {
    density = std::move(values);
    density_max = density.empty() ? 0.0 : *std::max_element(density.begin(), density.end());
    error_weights.clear();
    for (double d : density) error_weights.push_back(density_weight(d / density_max));
  }
};

// Builds the shape from a cleaned input. Meshes take their normals and areas from the faces
// (flipped as a whole if the mesh is oriented inward); clouds need normals (InvalidInput
// otherwise).
Shape build_shape(const SurfaceInput& input, const ShapeOptions& options);

// The shape seen from afar, for the first rounds of a run: about `budget` vertices, one per cell
// of a voxel grid and dominant normal direction (so that the two sides of a thin part stay
// apart; src/core/subsample.hpp). A coarse vertex is its cell's point (position, normal) and
// carries the cell's total area, summed quadric (quadrics add up exactly) and area-weighted mean
// density; two coarse vertices are neighbours when some of their members are. The shape itself when
// it has no more vertices.
Shape coarsen_shape(const Shape& shape, std::size_t budget);

}  // namespace vmas

#pragma GCC visibility pop
