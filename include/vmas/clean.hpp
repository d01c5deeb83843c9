#pragma once
// The cleaning stage, the first every input goes through (the readers call it; so does the
// one-call vmas::skeletonize for data that did not come from a file).
#include <array>
#include <cstddef>
#include <vector>

#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// Coordinates beyond this magnitude are rejected: squared distances would overflow.
constexpr double kMaxCoordinate = 1e150;

// What clean_surface() removed so that the shape is usable (duplicates, NaN/Inf, degenerate faces).
struct CleanReport {
  std::size_t non_finite_points = 0;  // points with a NaN coordinate (dropped)
  std::size_t missing_normals = 0;    // kept points whose normal is NaN, infinite or zero (left
                                      // NaN: preparation estimates it)
  std::size_t duplicate_points = 0;   // points at the same coordinates as an earlier one (merged)
  std::size_t degenerate_faces = 0;   // faces with a repeated or dropped vertex, or zero area
  std::size_t unused_points = 0;      // mesh vertices referenced by no face (dropped)
  std::vector<int> kept;  // index, in the surface as given, of every point kept (ascending)
  std::size_t total() const {
    return non_finite_points + duplicate_points + degenerate_faces + unused_points;
  }
};

// Removes points with a NaN coordinate (scanners' "no point here"), merges exact duplicates
// (remapping faces), drops degenerate faces and, for meshes, unreferenced vertices. Normals are
// renormalised; a point whose normal is NaN, infinite or zero keeps its place with a NaN normal
// (preparation estimates it; when no point has one, the cloud has no normals). Faces with area
// below 1e-14 * (bbox diagonal)^2 are degenerate. Kept points stay in input order, each duplicate
// group keeping its first point (with the group's mean density). Throws InvalidInput if `normals`
// or `density` is neither empty nor one per point, or if a coordinate is infinite or beyond +-1e150
// (squared distances would overflow).
CleanReport clean_surface(SurfaceInput& surface);

// What makes a mesh a poor description of a solid, counted over its (undirected) edges.
struct MeshDefects {
  std::size_t boundary_edges = 0;      // on one face only: holes, an open mesh
  std::size_t non_manifold_edges = 0;  // on more than two faces
  std::size_t misoriented_edges = 0;   // its two faces run along it the same way: neighbouring
                                       // faces disagree on which side is outside
  // A mesh without any of these bounds a volume (its winding number is exactly 1 inside).
  bool closed() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0;
  }
};
// Vertex indices are those of a cleaned surface (never negative; InvalidInput otherwise).
MeshDefects mesh_defects(const std::vector<std::array<int, 3>>& faces);

}  // namespace vmas

#pragma GCC visibility pop
