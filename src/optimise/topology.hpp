#pragma once
// What the optimisation does about a skeleton's topology (issue 50; the measures themselves,
// medial_topology and surface_genus, are public: vmas/eval.hpp).
#include <array>
#include <vector>

#include "vmas/eval.hpp"
#include "vmas/types.hpp"

namespace vmas {

// `medial` less its closing triangles (their edges stay): no cavity, the same pieces and loops.
MedialMesh without_cavities(MedialMesh medial);

// `medial` with its shortest loops filled until it has `loops` of them (b1) or no shorter
// candidate is left: the medial axis of a solid of genus g has g loops, and the extra ones of a
// skeleton are rings of spheres around a tube, short beside the loop around a handle. A loop is
// the shortest cycle of centres through one of its edges; it is filled with triangles between
// its spheres (an ear of the shortest diagonal at a time), whose new edges are listed. No
// sphere is added or moved, no cavity is made. `filled` (optional): how many loops were filled.
MedialMesh fill_extra_loops(MedialMesh medial, int loops, int* filled = nullptr);
// The loops fill_extra_loops fills, in its order: each as its spheres around it.
std::vector<std::vector<int>> extra_loops(const MedialMesh& medial, int loops);

// `medial` less the triangles of `candidates` (sorted spheres; connectivity.hpp's
// triangles_meeting_nowhere) whose removal adds a loop, the widest first, until it has `loops`
// loops or none is left: cluster adjacency makes every three clusters that touch pairwise a
// triangle, and around a handle that triangle fills the handle's loop. `opened` (optional): how
// many loops were opened.
MedialMesh open_missing_loops(MedialMesh medial, int loops,
                              const std::vector<std::array<int, 3>>& candidates,
                              int* opened = nullptr);

}  // namespace vmas
