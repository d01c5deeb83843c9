#pragma once
// Topology of a skeleton and of the shape it stands for (issue 50). The medial axis of a solid
// has the solid's topology: one piece per piece of the solid, one independent loop per handle
// (the genus), no enclosed cavity. The paper does not guarantee it (§5: "extra cavities").
#include <cstddef>
#include <string>
#include <vector>

#include "vmas/clean.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// Betti numbers over Z/2 of a medial mesh as a simplicial complex: its spheres, its edges and
// the edges of its triangles, its triangles (a triangle listed twice counts once, as a
// duplicate).
struct MedialTopology {
  int components = 0;  // b0
  int loops = 0;       // b1: independent cycles of edges that no triangles fill
  int cavities = 0;    // b2: closed pockets of triangles
  std::size_t duplicate_triangles = 0;
  // Triangles (indices, ascending) that each close a cavity with triangles whose slabs reach
  // out further (by the area of the centres' triangle plus the squared sum of the radii):
  // removing them all leaves no cavity, the same pieces and the same loops, and opens each
  // cavity where its wall covers least.
  std::vector<int> closing_triangles;
};
MedialTopology medial_topology(const MedialMesh& medial);

// `medial` less its closing triangles (their edges stay): no cavity, the same pieces and loops.
MedialMesh without_cavities(MedialMesh medial);

// The genus of each piece of a closed triangle mesh, from its Euler characteristic
// (V − E + F = 2 − 2g), pieces in the order of their first face. Known only for a mesh without
// boundary, non-manifold or misoriented edges whose characteristic is even and at most 2 per
// piece; otherwise `why` says why not.
struct SurfaceGenus {
  bool known = false;
  std::vector<int> genus;  // per piece
  std::string why;         // when not known
};
// `defects`: mesh_defects(mesh.faces), which the caller has already (ignored for a cloud).
SurfaceGenus surface_genus(const SurfaceInput& mesh, const MeshDefects& defects);

}  // namespace vmas

#pragma GCC visibility pop
