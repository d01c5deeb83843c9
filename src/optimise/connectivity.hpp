#pragma once
// Connectivity (paper §3.5): the dual of the partition. Two spheres are joined by an edge when
// their clusters touch across an edge of the neighbour graph, and three mutually adjacent
// clusters give a triangle.
#include <array>
#include <vector>

#include "vmas/skeletonizer.hpp"

namespace vmas {

// Sorted, symmetric adjacency lists of the clusters 0..cluster_count-1.
std::vector<std::vector<int>> cluster_adjacency(const Shape& shape, const std::vector<int>& labels,
                                                int cluster_count);

// Edges (i < j, every adjacent pair, face edges included) and faces (i < j < k, every 3-clique).
MedialMesh build_medial_mesh(const std::vector<Sphere>& spheres,
                             const std::vector<std::vector<int>>& adjacency);

// The triangles of `mesh` (build_medial_mesh of the clusters `labels`) whose three clusters meet
// nowhere on the shape: no vertex has all three among its own and its neighbours' clusters.
// Sorted spheres, ascending. Three clusters around a handle touch pairwise and leave the hole
// between them: their triangle fills the handle's loop.
std::vector<std::array<int, 3>> triangles_meeting_nowhere(const Shape& shape,
                                                          const std::vector<int>& labels,
                                                          const MedialMesh& mesh);

// Connected components of the shape's neighbour graph, and of a medial mesh's edges and faces
// (an isolated sphere is a component of its own).
int component_count(const Shape& shape);
int component_count(const MedialMesh& mesh);

}  // namespace vmas
