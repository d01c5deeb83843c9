#pragma once
// What the optimisation does about a skeleton's topology (issue 50; the measures themselves,
// medial_topology and surface_genus, are public: vmas/eval.hpp).
#include "vmas/eval.hpp"
#include "vmas/types.hpp"

namespace vmas {

// `medial` less its closing triangles (their edges stay): no cavity, the same pieces and loops.
MedialMesh without_cavities(MedialMesh medial);

}  // namespace vmas
