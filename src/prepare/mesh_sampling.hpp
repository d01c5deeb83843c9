#pragma once
// Coarse meshes: a CAD exporter places vertices only where the outline bends, so a flat face or a
// straight wall is a few long, thin triangles and the method, which partitions vertices, sees
// almost nothing of it (a few vertices per sphere, none inside a face). Such a mesh has its
// faces sampled by splitting their long edges (paper §5: "upsampling of the object"). The
// surface stays the same: the new vertices lie on the old faces, so the winding number and the
// error are those of the same solid.
#include <cstddef>

#include "vmas/types.hpp"

namespace vmas {

struct MeshSampling {
  std::size_t vertices_before = 0;  // 0: the mesh was dense enough and is left as it is
  double edge_limit = 0.0;          // edges longer than this were split (absolute)
};

// A mesh is coarse when more than 1 % of its area lies in long, thin faces: an edge longer than
// three times the spacing s = √(area / 10 000) of 10 000 points spread evenly over the mesh, and
// the face's height on it less than a quarter of it; or in faces of any shape with an edge longer
// than 10 s (a low-poly model: about a hundred evenly spread vertices or fewer; CGAL's double
// torus of 231 uneven ones fell into 49 pieces at 100 spheres). A mesh of well-shaped faces
// shorter than that is left alone: sampling it gave worse skeletons than its own vertices. Its
// faces are then sampled in rounds until no edge can be split:
//  - an edge longer than 1.5 s is split at its midpoint, unless a vertex on the same side of the
//    surface (its normal not facing away) lies within 0.75 s of it: of the long sides of a fan of
//    slivers, one in a few gets vertices, and the new vertices are 0.75 s apart at least, so
//    there are at most a few times 10 000 of them;
//  - a face with one, two or three split edges becomes two, three or four faces, turning the
//    same way (two faces that share an edge split it at the same vertex);
//  - two faces that lie in one plane (within 0.01 s) have their common edge flipped while the
//    angles facing it sum to more than π (Lawson's flips): the slivers left between split edges
//    become faces between the new vertices, which the next round splits further.
// Every new vertex lies on the old surface, after the old vertices, which keep their indices. A
// dense mesh, or anything but a mesh, is left untouched (byte-identical).
MeshSampling sample_coarse_mesh(SurfaceInput& mesh);

}  // namespace vmas
