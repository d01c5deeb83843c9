#pragma once
// Smoothing a noisy scan before normals and skeleton are computed: moving-least-squares
// projection (PCL's) for clouds, with its bias put back, and smoothing along the faces for meshes.
#include <array>
#include <vector>

#include "vmas/types.hpp"

namespace vmas {

// Projects every point onto the local quadric surface of PCL's MovingLeastSquares with support
// `radius` (fitted on a voxel grid of radius / 6, at the grid sample nearest to the point), and
// returns the unoriented surface normals there. A point without a valid fit nearby keeps its
// position and gets a NaN normal (orient_normals repairs it).
std::vector<Vec3> smooth_mls(std::vector<Vec3>& points, double radius);

// Smooths a noisy mesh's vertices along its own faces and keeps the faces: Taubin's λ|μ filter
// (λ = 0.5, μ = −0.53: a low-pass filter that does not shrink the shape as plain Laplacian
// smoothing does), `steps` pairs of passes with uniform weights over each vertex's edge
// neighbours. The faces say which vertices belong to the same sheet, so the two sides of a thin
// part never merge (they do under a smoothing by distance, such as MLS), and the uniform weights
// also even out the vertices along the surface, which unfolds faces that noise has folded.
// Vertices on no edge stay. Deterministic whatever the thread count. Returns the RMS distance
// by which the vertices moved across the smoothed surface (along its vertex normals): the noise,
// where local fits to strong noise read it low.
double smooth_mesh(std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces,
                   int steps);

// Moves every point of `smoothed` (smooth_mls of `raw` with radius `support`, in the same order)
// along its unit normal (NaN: stays) by the mean offset along that normal of the raw points from
// their smoothed positions: the mean residual vector over the points within half the support (at
// least the 128 nearest) of an even subset (every ⌊n / 8000⌋-th point), blended between the 4
// subset points nearest to the point. A large support's fit rounds curved parts off and pulls
// them toward their centre (the bear at σ = 3 %: 1.8 % of the diagonal inward), while the noise
// itself averages out: the residuals' local mean is the smoothing's bias (Tukey's "twicing").
void restore_smoothing_bias(std::vector<Vec3>& smoothed, const std::vector<Vec3>& normals,
                            const std::vector<Vec3>& raw, double support);

}  // namespace vmas
