#pragma once
// Scan noise: how much there is (a robust scale of the residuals to local quadric fits), and
// its removal before normals and skeleton are computed: statistical outlier removal (PCL's rule,
// computed over vmas's own neighbour searches) and moving-least-squares projection (PCL's) for
// clouds, smoothing along the faces for meshes.
#include <array>
#include <vector>

#include "vmas/prepare.hpp"

namespace vmas {

// The smallest neighbourhood estimate_noise fits (NoiseEstimate::neighbours).
inline constexpr int kFewestNoiseNeighbours = 16;

// Fits a quadric height field to the k nearest neighbours of evenly spread points (within an even
// subset of 10 000 points) and takes the median RMS residual, at the smallest k in 16, 32, ...
// 2048 whose neighbourhood radius is at least three times that residual (smaller neighbourhoods
// lie inside the noise and underestimate it). Clean samples of a smooth surface give a tiny
// fraction of the spacing; sharp edges touch too few points to move the median. Deterministic.
// Throws InvalidInput for fewer than kFewestNoiseNeighbours points.
NoiseEstimate estimate_noise(const std::vector<Vec3>& points);

// True when `noise` calls for smoothing under `options`.
bool is_noisy(const NoiseEstimate& noise, const DenoiseOptions& options);

// Indices of the points kept by the rule of PCL's StatisticalOutlierRemoval (mean distance to
// the outlier_k nearest neighbours within outlier_deviations standard deviations of the cloud's
// mean; the filter keeps its searcher private, so the rule is computed here), ascending; repeated (at most 4 passes) while a pass removes between 0.5 % and 2 % of
// the points. A first pass removing more than 2 % has found uneven density: every point stays.
// Clouds too small for it keep every point.
std::vector<int> inlier_indices(const std::vector<Vec3>& points, const DenoiseOptions& options);

// `inliers` (from inlier_indices) and the points it left out that continue the sampling of their
// nearest kept neighbour, near it or on its plane, ascending: for a clean sampling, whose sparse
// parts (a random sampling's sparse tail, the rim of a regular grid, a thin wall) the
// statistical rule takes for strays. When most of the points left out do not continue it, they
// are a scatter of strays, and only those on their neighbour's surface join `inliers`.
std::vector<int> with_sparse_parts(const std::vector<Vec3>& points, const std::vector<int>& inliers,
                                   const DenoiseOptions& options);

// Projects every point onto the local quadric surface of PCL's MovingLeastSquares with support
// `radius` (fitted on a voxel grid of radius / 6, at the grid sample nearest to the point), and
// returns the unoriented surface normals there. A point without a valid fit nearby keeps its
// position and gets a NaN normal (orient_normals repairs it).
std::vector<Vec3> smooth_mls(std::vector<Vec3>& points, double radius);

// Indices of the `smoothed` points (smooth_mls of `raw`, in the same order) that the noisy data
// support, ascending. Noise spreads a sampling past its surface's edges and tips (a wing's, a
// finger's) by two or three deviations, and smoothing along the normals keeps that fringe, on
// which spheres then sit outside the shape. A fringe point has few raw points within `radius`
// (the smoothing's scale, at least two spacings) against the smoothed points around it (within
// 3 radii): under 0.3 of their upper quartile, it goes; so does a point with no other within 3
// radii. A uniformly sparse part of a scan (far from the scanner) keeps its points: the points
// around are as sparse. When the points kept would fall into more pieces than all of them (as
// the shape's graph joins them: cloud_graph.hpp), the trim cut through a thin part: the dropped
// points there that best rejoin the pieces come back, and if the pieces still are more, every
// point is returned.
std::vector<int> supported_by_noise(const std::vector<Vec3>& smoothed, const std::vector<Vec3>& raw,
                                    double radius);

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

// The robust deviation (median distance / 0.6745) by which smooth_mls(points, radius) would move
// the points, measured at about `samples` of them spread evenly through the array: the surface
// is fitted only where they are, and each distance is the one smooth_mls gives that point.
// Throws InvalidOption when samples < 1 or radius <= 0.
double mls_deviation(const std::vector<Vec3>& points, double radius, int samples);

}  // namespace vmas
